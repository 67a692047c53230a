#pragma once
// One GL context and renderer per test process (gtest_discover_tests runs each test in its
// own process, so this is one per test). The backend is OSMesa unless CLIPRAY_TEST_GL_BACKEND
// names another ("egl"): the same suite then runs on whatever EGL offers, a GPU included.

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/Renderer.hpp"

namespace clipray::testing {

inline std::string glBackendForTests() {
  const char* requested = std::getenv("CLIPRAY_TEST_GL_BACKEND");
  return requested && *requested ? requested : "osmesa";
}

inline std::unique_ptr<gl::GlContext> createContextForTests() {
  return gl::createContext(glBackendForTests());
}

class GlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    context_ = createContextForTests();
    renderer_ = std::make_unique<gl::Renderer>(*context_);
  }
  static void TearDownTestSuite() {
    renderer_.reset();
    context_.reset();
  }
  static gl::Renderer& renderer() { return *renderer_; }

 private:
  static inline std::unique_ptr<gl::GlContext> context_;
  static inline std::unique_ptr<gl::Renderer> renderer_;
};

inline std::string sourcePath(const std::string& relative) {
  return std::string(CLIPRAY_SOURCE_DIR) + "/" + relative;
}

}  // namespace clipray::testing

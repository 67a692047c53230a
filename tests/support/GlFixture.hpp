#pragma once
// One OSMesa context and renderer per test process (gtest_discover_tests runs each test in its
// own process, so this is one per test).

#include <gtest/gtest.h>

#include <memory>

#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/ReconcileRun.hpp"
#include "clipray/gl/Renderer.hpp"

namespace clipray::testing {

class GlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    context_ = gl::createOsMesaContext();
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

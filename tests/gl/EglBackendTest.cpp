// The EGL backend: a surfaceless GL 4.5 core context that renders the same FBO path as OSMesa.
// On Mesa llvmpipe both backends must produce bit-identical depth and id frames for every shipped
// scene, convention, depth format and vertex mode.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

using testing::sourcePath;

// Sets an environment variable for one test and restores it afterwards (ctest runs each test in
// its own process, but a developer may run the whole binary at once).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// An EGL context, or the reason there is none (the tests skip with it).
std::unique_ptr<gl::GlContext> tryEgl(std::string& reason) {
  try {
    return gl::createEglContext();
  } catch (const gl::BackendError& error) {
    reason = error.what();
    return nullptr;
  }
}

struct FrameKey {
  std::string scene, camera;
  DepthMode mode;
  DepthFormat format;
  VertexMode vertexMode;
  std::string describe() const {
    return scene + "/" + camera + " " + mode.name() + " " + depthFormatName(format) + " " +
           vertexModeName(vertexMode);
  }
};

// Every shipped scene x camera x {no, zo, zo-reversed} x {16, 24, 32f} x every vertex mode, at a
// reduced size (the frames of one backend are kept in memory until the other has drawn them).
std::vector<std::pair<FrameKey, RasterFrame>> renderEverything(gl::GlContext& context,
                                                               std::string* rendererName) {
  gl::Renderer renderer(context);
  if (rendererName) *rendererName = renderer.info().renderer;
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::directory_iterator(sourcePath("scenes"))) {
    if (entry.path().extension() == ".json") paths.push_back(entry.path());
  }
  std::sort(paths.begin(), paths.end());
  std::vector<std::pair<FrameKey, RasterFrame>> frames;
  for (const auto& path : paths) {
    const Scene scene = loadScene(path.string());
    for (const Camera& camera : scene.cameras) {
      const Viewport viewport{160, 120};
      for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
        gl::RenderRequest request;
        request.scene = &scene;
        request.viewport = viewport;
        request.mode = mode;
        request.clipFromWorld = camera.clipFromWorld(mode, viewport);
        request.vertexReference = engine::nearPlaneCentre(request.clipFromWorld, mode);
        for (const DepthFormat format :
             {DepthFormat::Unorm16, DepthFormat::Unorm24, DepthFormat::Float32}) {
          for (const VertexMode vertexMode :
               {VertexMode::World, VertexMode::CameraRelative, VertexMode::Pretransformed}) {
            request.depthFormat = format;
            request.vertexMode = vertexMode;
            frames.emplace_back(FrameKey{scene.name, camera.name, mode, format, vertexMode},
                                renderer.render(request));
          }
        }
      }
    }
  }
  return frames;
}

TEST(EglBackend, MatchesOsMesaBitForBitOnLlvmpipe) {
  // Mesa's surfaceless platform on llvmpipe: the same rasterizer OSMesa uses.
  const ScopedEnv platform("CLIPRAY_EGL_PLATFORM", "surfaceless");
  const ScopedEnv software("LIBGL_ALWAYS_SOFTWARE", "1");
  std::string osMesaRenderer, eglRenderer;
  std::vector<std::pair<FrameKey, RasterFrame>> reference;
  {
    // One backend at a time: the renderer and its context are gone before the other is created.
    std::unique_ptr<gl::GlContext> osMesa = gl::createOsMesaContext();
    reference = renderEverything(*osMesa, &osMesaRenderer);
  }
  std::string reason;
  std::unique_ptr<gl::GlContext> egl = tryEgl(reason);
  if (!egl) GTEST_SKIP() << "EGL cannot create a context here: " << reason;
  const std::vector<std::pair<FrameKey, RasterFrame>> frames = renderEverything(*egl, &eglRenderer);
  if (osMesaRenderer.find("llvmpipe") == std::string::npos ||
      eglRenderer.find("llvmpipe") == std::string::npos) {
    GTEST_SKIP() << "bit-identity holds on llvmpipe only; OSMesa renders with \"" << osMesaRenderer
                 << "\", EGL with \"" << eglRenderer << "\"";
  }
  ASSERT_EQ(frames.size(), reference.size());
  EXPECT_GE(frames.size(), 10u * 3 * 3 * 3);
  int identical = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const FrameKey& key = frames[k].first;
    const RasterFrame& ours = frames[k].second;
    const RasterFrame& theirs = reference[k].second;
    ASSERT_EQ(key.describe(), reference[k].first.describe());
    ASSERT_EQ(ours.depth.size(), theirs.depth.size()) << key.describe();
    const bool sameDepth =
        std::memcmp(ours.depth.data(), theirs.depth.data(), ours.depth.size() * sizeof(float)) == 0;
    EXPECT_TRUE(sameDepth) << key.describe() << ": depth differs between EGL and OSMesa";
    EXPECT_EQ(ours.ids, theirs.ids) << key.describe() << ": ids differ between EGL and OSMesa";
    identical += sameDepth && ours.ids == theirs.ids;
  }
  EXPECT_EQ(identical, static_cast<int>(frames.size()));
  // Not a vacuous comparison: the frames show geometry.
  std::size_t covered = 0;
  for (const auto& [key, frame] : frames) {
    for (const std::uint32_t id : frame.ids) covered += id != 0;
  }
  EXPECT_GT(covered, frames.size() * 160 * 120 / 10);
}

TEST(EglBackend, ReconcilesTheStandardSceneConsistently) {
  std::string reason;
  std::unique_ptr<gl::GlContext> egl = tryEgl(reason);
  if (!egl) GTEST_SKIP() << "EGL cannot create a context here: " << reason;
  gl::Renderer renderer(*egl);
  EXPECT_EQ(renderer.info().backend, "egl");
  EXPECT_NE(renderer.info().version.find("4.5"), std::string::npos) << renderer.info().version;
  const Scene scene = loadScene(sourcePath("scenes/standard.json"));
  const Camera& camera = scene.cameras[0];
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    const RunRecord run = engine::rasterAndCompare(
        renderer, engine::runAnalyticPass(scene, camera, mode, camera.viewport),
        DepthFormat::Float32, VertexMode::World, false);
    EXPECT_TRUE(run.metrics.consistent()) << mode.name();
    EXPECT_GT(run.metrics.rasterHits, 0) << mode.name();
  }
}

TEST(EglBackend, IsListedAndCreatedByName) {
  const std::vector<std::string> names = gl::backendNames();
  EXPECT_EQ(names, (std::vector<std::string>{"osmesa", "egl"}));
  std::string reason;
  if (!tryEgl(reason)) GTEST_SKIP() << "EGL cannot create a context here: " << reason;
  EXPECT_EQ(gl::createContext("egl")->backendName(), "egl");
}

TEST(EglBackend, AMissingLibraryIsABackendErrorNamingThePath) {
  const ScopedEnv library("CLIPRAY_EGL_LIBRARY", "/nonexistent/libEGL.so.1");
  try {
    gl::createEglContext();
    FAIL() << "expected a BackendError";
  } catch (const gl::BackendError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("EGL: cannot load /nonexistent/libEGL.so.1 (", 0), 0u)
        << error.what();
  }
}

TEST(EglBackend, ALibraryWithoutEglIsABackendError) {
  const ScopedEnv library("CLIPRAY_EGL_LIBRARY", "libm.so.6");  // loads, has no EGL
  try {
    gl::createEglContext();
    FAIL() << "expected a BackendError";
  } catch (const gl::BackendError& error) {
    EXPECT_STREQ(error.what(), "EGL: eglGetProcAddress missing from the loaded library");
  }
}

TEST(EglBackend, AnUnknownPlatformChoiceIsABackendError) {
  const ScopedEnv platform("CLIPRAY_EGL_PLATFORM", "wayland");
  try {
    gl::createEglContext();
    FAIL() << "expected a BackendError";
  } catch (const gl::BackendError& error) {
    EXPECT_STREQ(error.what(),
                 "EGL: CLIPRAY_EGL_PLATFORM: unknown value \"wayland\"; expected one of: auto, "
                 "surfaceless, device");
  }
}

}  // namespace
}  // namespace clipray

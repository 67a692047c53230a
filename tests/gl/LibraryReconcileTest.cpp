// clipray::reconcile, the public entry point: options refused with their field named, the worst
// pixels of a run, and an app render function's mistakes named instead of compared.

#include <glad/gl.h>

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "clipray/Reconcile.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/math/Projections.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

const float kQuadPositions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
const std::uint32_t kQuadIndices[] = {0, 1, 2, 0, 2, 3};

TestScene quadScene() {
  const glm::dmat4 clipFromWorld =
      perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0, kZeroToOne) *
      viewFromWorldLookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  return SceneBuilder("quad")
      .mesh("quad", kQuadPositions, kQuadIndices)
      .camera("main", clipFromWorld, {64, 48})
      .build();
}

// The library's default options on the backend the suite runs on (OSMesa unless
// CLIPRAY_TEST_GL_BACKEND says otherwise).
ReconcileOptions defaultOptions() {
  ReconcileOptions options;
  options.backend = testing::glBackendForTests();
  return options;
}

std::string messageOf(const ReconcileOptions& options) {
  try {
    reconcile(quadScene(), robustPickRays(), options);
  } catch (const std::exception& error) {
    return error.what();
  }
  return "no error";
}

TEST(LibraryReconcile, ClipraysOwnRaysAndRasterAgree) {
  const ReconcileResult result = reconcile(quadScene(), robustPickRays(), defaultOptions());
  ASSERT_EQ(result.runs.size(), 1u);  // the scene names no conventions: zo
  const RunResult& run = result.runs[0];
  EXPECT_TRUE(run.consistent) << result.text();
  EXPECT_EQ(run.convention, "zo");
  EXPECT_EQ(run.depthFormat, "32f");
  EXPECT_EQ(run.pixels, 64 * 48);
  // The quad's 2x2 at distance 3 under a 60 degree fov at 4:3 covers |x_ndc| < 0.433 and
  // |y_ndc| < 0.577: the centres of columns 18..45 and rows 10..37.
  EXPECT_EQ(run.rayHits, 28 * 28);
  EXPECT_EQ(run.rasterHits, 28 * 28);
  EXPECT_EQ(run.depthCompared + run.idMismatches, 28 * 28);
  EXPECT_EQ(run.worstPixels.size(), 5u);
  // A consistent run's worst pixels are its largest depth errors against their tolerance.
  EXPECT_EQ(run.worstPixels[0].pixelClass, "agree");
  EXPECT_EQ(static_cast<float>(run.worstPixels[0].toleranceRatio),
            static_cast<float>(run.worstToleranceRatio));
  EXPECT_LE(run.worstPixels[1].toleranceRatio, run.worstPixels[0].toleranceRatio);
  EXPECT_TRUE(result.reportDirectory.empty());
}

TEST(LibraryReconcile, OptionsAreRefusedByField) {
  ReconcileOptions options = defaultOptions();
  options.cameras = {"side"};
  EXPECT_EQ(messageOf(options),
            "ReconcileOptions: cameras: no camera \"side\" in scene \"quad\" (it has \"main\")");
  options = defaultOptions();
  options.depthFormats.clear();
  EXPECT_EQ(messageOf(options),
            "ReconcileOptions: depthFormats: expected at least one depth format, got none");
  options = defaultOptions();
  options.render = [](const AppFrame&) {};
  options.vertexMode = VertexMode::CameraRelative;
  EXPECT_EQ(messageOf(options),
            "ReconcileOptions: vertexMode: the app's render function draws its own vertices; "
            "expected world, got camera-relative");
  options = defaultOptions();
  AppWindow window;
  window.viewportX = 10;
  window.framebufferWidth = 70;
  options.window = window;
  options.render = [](const AppFrame&) {};
  EXPECT_EQ(messageOf(options),
            "ReconcileOptions: window: a 70x48 framebuffer cannot hold camera \"main\"'s 64x48 "
            "viewport at (10, 0)");
}

// ReconcileOptions::samples: a run per sample, each consistent. The quad's edges cross pixels
// (its left edge at window x 18.1), so each sample's coverage is its own: the same on both sides.
TEST(LibraryReconcile, EverySampleOfAMultisampledFrameIsARun) {
  ReconcileOptions options = defaultOptions();
  options.samples = 4;
  const ReconcileResult result = reconcile(quadScene(), robustPickRays(), options);
  ASSERT_EQ(result.runs.size(), 4u) << result.text();
  for (int s = 0; s < 4; ++s) {
    const RunResult& run = result.runs[static_cast<std::size_t>(s)];
    EXPECT_TRUE(run.consistent) << result.text();
    EXPECT_EQ(run.sample, s);
    EXPECT_EQ(run.sampleCount, 4);
    EXPECT_EQ(run.frameUnexplainedPixels, 0);
    EXPECT_EQ(run.rasterHits, run.rayHits) << s;
  }
  // An app's render function draws multisampled too (tests/consumer), but its draw calls cannot
  // be numbered per sample.
  options.render = [](const AppFrame&) {};
  options.appIds = AppIds::PerDrawCall;
  EXPECT_EQ(messageOf(options),
            "ReconcileOptions: samples 4: one id per draw call (AppIds::PerDrawCall) is read from "
            "the stencil buffer, one value per pixel; a multisampled app frame needs its ids "
            "written per fragment (AppIds::Written)");
}

// A scene that says its app draws with MSAA (SceneBuilder::samples) is reconciled per sample
// unless the options say otherwise; a count the implementation does not offer names the scene.
TEST(LibraryReconcile, AScenesOwnSampleCountIsUsedUnlessTheOptionsSetOne) {
  const glm::dmat4 clipFromWorld =
      perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0, kZeroToOne) *
      viewFromWorldLookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  const auto scene = [&](int samples) {
    return SceneBuilder("msaa-quad")
        .samples(samples)
        .mesh("quad", kQuadPositions, kQuadIndices)
        .camera("main", clipFromWorld, {64, 48})
        .build();
  };
  ReconcileOptions options = defaultOptions();
  const ReconcileResult sampled = reconcile(scene(4), robustPickRays(), options);
  ASSERT_EQ(sampled.runs.size(), 4u) << sampled.text();
  EXPECT_EQ(sampled.runs[3].sample, 3);
  EXPECT_EQ(sampled.runs[3].sampleCount, 4);
  EXPECT_TRUE(sampled.consistent()) << sampled.text();
  options.samples = 1;
  const ReconcileResult single = reconcile(scene(4), robustPickRays(), options);
  ASSERT_EQ(single.runs.size(), 1u) << single.text();
  EXPECT_EQ(single.runs[0].sampleCount, 1);
  options.samples = 0;
  try {
    reconcile(scene(3), robustPickRays(), options);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("SceneBuilder \"msaa-quad\": /samples 3: ", 0), 0u) << message;
    EXPECT_NE(message.find(") offers no 3-sample depth format 32f (it offers "), std::string::npos)
        << message;
  }
}

TEST(LibraryReconcile, AnAppThatDrawsDepthWithoutIdsIsTold) {
  ReconcileOptions options = defaultOptions();
  options.render = [](const AppFrame&) {
    glClearDepth(0.25);  // depth no clear value of any convention, and no ids
    glClear(GL_DEPTH_BUFFER_BIT);
  };
  EXPECT_EQ(messageOf(options),
            "the app's render function drew depth but wrote no ids to colour attachment 1 "
            "(layout(location = 1) out uint: firstId(mesh) + gl_PrimitiveID; or reconcile with "
            "one id per draw call, AppIds::PerDrawCall)");
}

TEST(LibraryReconcile, AnAppThatWritesIdsTheSceneLacksIsTold) {
  ReconcileOptions options = defaultOptions();
  options.render = [](const AppFrame& frame) {
    const GLuint ids[4] = {7, 0, 0, 0};  // the quad's ids are 1 and 2
    glClearBufferuiv(GL_COLOR, 1, ids);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    EXPECT_EQ(frame.firstId(0), 1u);
  };
  EXPECT_EQ(messageOf(options),
            "the app's render function wrote id 7 at pixel (0, 0) of colour attachment 1; the "
            "scene's ids end at 2 (write firstId(mesh) + gl_PrimitiveID, and clear depth only: a "
            "colour clear of the integer attachment is undefined)");
}

TEST(LibraryReconcile, AnAppThatLeavesAGlErrorIsTold) {
  ReconcileOptions options = defaultOptions();
  options.render = [](const AppFrame&) { glEnable(0xFFFF); };
  EXPECT_EQ(messageOf(options), "GL: the app's render function left GL error 0x0500");
  options.render = [](const AppFrame&) { glBindFramebuffer(GL_FRAMEBUFFER, 0); };
  EXPECT_EQ(messageOf(options).substr(0, 61),
            "GL: the app's render function bound framebuffer 0 and left it");
}

TEST(LibraryReconcile, AnAppThatDrawsNothingIsInconsistent) {
  ReconcileOptions options = defaultOptions();
  options.render = [](const AppFrame&) {
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
  };
  const ReconcileResult result = reconcile(quadScene(), robustPickRays(), options);
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent);
  EXPECT_TRUE(result.runs[0].appRender);
  EXPECT_EQ(result.runs[0].rasterHits, 0);
  EXPECT_EQ(result.runs[0].coverageUnexplained + 0,
            result.runs[0].rayHits -
                (result.runs[0].coverageMismatches - result.runs[0].coverageUnexplained));
  EXPECT_EQ(result.runs[0].worstPixels.at(0).rasterHit, "nothing");
  EXPECT_EQ(result.runs[0].worstPixels.at(0).rayHit.substr(0, 16), "\"quad\" triangle ");
  EXPECT_NE(result.text().find("(app render)"), std::string::npos);
}

TEST(LibraryReconcile, OneIdPerDrawCallCountsTheAppsDrawCalls) {
  ReconcileOptions options = defaultOptions();
  options.appIds = AppIds::PerDrawCall;
  // Two draw calls for a scene of one mesh, through the function the frame hands out.
  options.render = [](const AppFrame& frame) {
    const auto drawArrays =
        reinterpret_cast<PFNGLDRAWARRAYSPROC>(frame.getProcAddress("glDrawArrays"));
    GLuint vertexArray = 0;
    glCreateVertexArrays(1, &vertexArray);
    glBindVertexArray(vertexArray);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    drawArrays(GL_TRIANGLES, 0, 0);
    drawArrays(GL_TRIANGLES, 0, 0);
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vertexArray);
  };
  EXPECT_EQ(messageOf(options),
            "the app's render function made 2 draw calls; with one id per draw call, call k draws "
            "mesh k, and the scene has 1 meshes (at most 255)");
  options.depthFormats = {DepthFormat::Unorm16};
  EXPECT_EQ(messageOf(options),
            "ReconcileOptions: depthFormats: one id per draw call (AppIds::PerDrawCall) counts "
            "draws in the stencil buffer, which GL pairs with depth formats 24 and 32f only; got "
            "16");
}

}  // namespace
}  // namespace clipray

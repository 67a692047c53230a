// GL integration: every shipped scene reconciles under its conventions, with D32F and D24, in
// every vertex mode; glClipControl and reversed-Z demonstrably take effect.

#include <gtest/gtest.h>

#include <filesystem>

#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

using testing::GlTest;
using testing::sourcePath;

std::string describe(const RunRecord& run) {
  const RunMetrics& m = run.metrics;
  return run.scene + "/" + run.camera + " " + run.convention.name() + " " +
         depthFormatName(run.depthFormat) + " " + vertexModeName(run.vertexMode) + ": coverage " +
         std::to_string(m.coverageMismatch.total) + " (unexplained " +
         std::to_string(m.coverageMismatch.unexplained) + "), id " +
         std::to_string(m.idMismatch.total) + " (unexplained " +
         std::to_string(m.idMismatch.unexplained) + "), depth>tol " +
         std::to_string(m.depthBeyondTolerance) + ", tolerance ratio max " +
         std::to_string(m.toleranceRatio.max);
}

std::vector<DepthMode> conventionsOf(const Scene& scene) {
  return scene.conventions.empty() ? std::vector<DepthMode>{kNegativeOneToOne, kZeroToOne}
                                   : scene.conventions;
}

class ShippedScenes : public GlTest {};

TEST_F(ShippedScenes, EveryShippedSceneIsConsistent) {
  int runs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(sourcePath("scenes"))) {
    if (entry.path().extension() != ".json") continue;
    const Scene scene = loadScene(entry.path().string());
    for (const Camera& camera : scene.cameras) {
      for (const DepthMode mode : conventionsOf(scene)) {
        const gl::AnalyticPass pass = gl::runAnalyticPass(scene, camera, mode, camera.viewport);
        for (const DepthFormat format : {DepthFormat::Float32, DepthFormat::Unorm24}) {
          for (const VertexMode vertexMode :
               {VertexMode::World, VertexMode::CameraRelative, VertexMode::Pretransformed}) {
            const RunRecord run = gl::rasterAndCompare(renderer(), pass, format, vertexMode, false);
            ++runs;
            EXPECT_TRUE(run.metrics.consistent()) << describe(run);
            EXPECT_GT(run.metrics.rasterHits, 0) << describe(run);
            // Most hit pixels agree on the primitive, or on the depth where coplanar primitives
            // z-fight; edge-ambiguous pixels are the exception.
            EXPECT_GT(run.metrics.depthCompared + run.metrics.idMismatch.depthAmbiguous,
                      run.metrics.rayHits * 9 / 10)
                << describe(run);
          }
        }
      }
    }
  }
  EXPECT_GE(runs, 10 * 6);
}

TEST_F(ShippedScenes, ClipControlMovesTheNearPlaneOfANoMatrix) {
  const Scene scene = loadScene(sourcePath("scenes/no_matrix_under_zo.json"));
  const Camera& camera = scene.cameras[0];
  const auto underNo = gl::rasterAndCompare(
      renderer(), gl::runAnalyticPass(scene, camera, kNegativeOneToOne, camera.viewport),
      DepthFormat::Float32, VertexMode::World, false);
  const auto underZo = gl::rasterAndCompare(
      renderer(), gl::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport),
      DepthFormat::Float32, VertexMode::World, false);
  // Under ZO the slanted quad is clipped further out: fewer of its pixels, more of the wall behind.
  // The raster and the rays agree in both.
  EXPECT_TRUE(underNo.metrics.consistent()) << describe(underNo);
  EXPECT_TRUE(underZo.metrics.consistent()) << describe(underZo);
  const gl::AnalyticPass no =
      gl::runAnalyticPass(scene, camera, kNegativeOneToOne, camera.viewport);
  const gl::AnalyticPass zo = gl::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport);
  const PrimitiveIdTable ids(scene);
  auto slantedPixels = [&](const gl::AnalyticPass& pass) {
    int count = 0;
    for (const Hit& hit : pass.frame.hits)
      count += hit.hit() && ids.decode(hit.primitiveId).object == 0;
    return count;
  };
  EXPECT_LT(slantedPixels(zo), slantedPixels(no) * 9 / 10);
  EXPECT_GT(slantedPixels(zo), 0);
}

TEST_F(ShippedScenes, ReversedZStoresNearerSurfacesDeeper) {
  const Scene scene = loadScene(sourcePath("scenes/standard.json"));
  gl::RenderRequest request;
  request.scene = &scene;
  request.viewport = {64, 48};
  request.mode = kZeroToOneReversed;
  request.clipFromWorld = scene.cameras[0].clipFromWorld(kZeroToOneReversed, request.viewport);
  const RasterFrame reversed = renderer().render(request);
  request.mode = kZeroToOne;
  request.clipFromWorld = scene.cameras[0].clipFromWorld(kZeroToOne, request.viewport);
  const RasterFrame classic = renderer().render(request);
  // Same coverage and ids; background cleared to 0 under reversed-Z and to 1 otherwise.
  EXPECT_EQ(reversed.ids, classic.ids);
  for (std::size_t i = 0; i < reversed.ids.size(); ++i) {
    if (reversed.ids[i] == 0) {
      EXPECT_EQ(reversed.depth[i], 0.0f);
      EXPECT_EQ(classic.depth[i], 1.0f);
    }
  }
}

TEST_F(ShippedScenes, RendererReportsItsLimits) {
  const GlInfo& info = renderer().info();
  EXPECT_EQ(info.backend, "osmesa");
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_GE(info.subpixelBits, 4);  // the GL spec's minimum
  EXPECT_GE(renderer().maxViewport().width, 4096);
}

}  // namespace
}  // namespace clipray

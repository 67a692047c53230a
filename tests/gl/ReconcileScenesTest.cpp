// GL integration: every shipped scene reconciles under its conventions, with D32F and D24, in
// every vertex mode; glClipControl and reversed-Z demonstrably take effect.

#include <gtest/gtest.h>

#include <filesystem>

#include "clipray/rays/RobustRays.hpp"
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
        const engine::AnalyticPass pass =
            engine::runAnalyticPass(scene, camera, mode, camera.viewport);
        for (const DepthFormat format : {DepthFormat::Float32, DepthFormat::Unorm24}) {
          for (const VertexMode vertexMode :
               {VertexMode::World, VertexMode::CameraRelative, VertexMode::Pretransformed}) {
            const RunRecord run =
                engine::rasterAndCompare(renderer(), pass, format, vertexMode, false);
            ++runs;
            EXPECT_TRUE(run.metrics.consistent()) << describe(run);
            EXPECT_GT(run.metrics.rasterHits, 0) << describe(run);
            // Most hit pixels agree on the primitive, or on the depth where coplanar primitives
            // z-fight, or lie in front of the near plane (depth clamp); edge-ambiguous pixels
            // are the exception.
            EXPECT_GT(run.metrics.depthCompared + run.metrics.idMismatch.depthAmbiguous +
                          run.metrics.inFrontOfNear,
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
  const auto underNo = engine::rasterAndCompare(
      renderer(), engine::runAnalyticPass(scene, camera, kNegativeOneToOne, camera.viewport),
      DepthFormat::Float32, VertexMode::World, false);
  const auto underZo = engine::rasterAndCompare(
      renderer(), engine::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport),
      DepthFormat::Float32, VertexMode::World, false);
  // Under ZO the slanted quad is clipped further out: fewer of its pixels, more of the wall behind.
  // The raster and the rays agree in both.
  EXPECT_TRUE(underNo.metrics.consistent()) << describe(underNo);
  EXPECT_TRUE(underZo.metrics.consistent()) << describe(underZo);
  const engine::AnalyticPass no =
      engine::runAnalyticPass(scene, camera, kNegativeOneToOne, camera.viewport);
  const engine::AnalyticPass zo =
      engine::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport);
  const PrimitiveIdTable ids(scene);
  auto slantedPixels = [&](const engine::AnalyticPass& pass) {
    int count = 0;
    for (const Hit& hit : pass.frame.hits)
      count += hit.hit() && ids.decode(hit.primitiveId).object == 0;
    return count;
  };
  EXPECT_LT(slantedPixels(zo), slantedPixels(no) * 9 / 10);
  EXPECT_GT(slantedPixels(zo), 0);
}

TEST_F(ShippedScenes, AWaterReflectionShowsNothingBelowTheHorizonOrTheWater) {
  // Lengyel's oblique near plane at the water level, horizon in view: under each camera's own
  // convention (reflection_no under NO, reflection_zo under ZO) and the other, the pixels below
  // the horizon have no ray and the raster shows nothing there, and the run is consistent. Under
  // its own convention the near plane is the water: the submerged box and the sea floor show on
  // neither side. (Under the other the near plane is another plane through the line where the
  // water meets the eye's w = 0 plane: a ZO matrix under NO clips at z = -w, below the water,
  // and shows the submerged box; both sides agree on it.)
  const Scene scene = loadScene(sourcePath("scenes/water_reflection.json"));
  ASSERT_EQ(scene.cameras.size(), 2u);
  const PrimitiveIdTable ids(scene);
  for (const Camera& camera : scene.cameras) {
    for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
      SCOPED_TRACE(camera.name + " under " + mode.name());
      const engine::AnalyticPass pass =
          engine::runAnalyticPass(scene, camera, mode, camera.viewport);
      const RobustRayGenerator rays(pass.camera.clipFromWorld, mode);
      const bool ownConvention = camera.name == "reflection_" + mode.name();
      int noRay = 0;
      for (const VertexMode vertexMode : {VertexMode::World, VertexMode::Pretransformed}) {
        gl::RenderRequest request;
        request.scene = &scene;
        request.viewport = camera.viewport;
        request.mode = mode;
        request.clipFromWorld = pass.camera.clipFromWorld;
        request.vertexMode = vertexMode;
        const RasterFrame raster = renderer().render(request);
        noRay = 0;
        for (int y = 0; y < camera.viewport.height; ++y) {
          for (int x = 0; x < camera.viewport.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * camera.viewport.width + x;
            const bool hasRay = rays.generateForPixel(x, y, camera.viewport).tMax >= 0.0;
            noRay += hasRay ? 0 : 1;
            if (!hasRay) {
              EXPECT_EQ(raster.ids[i], 0u) << x << ", " << y;
            }
            for (const std::uint32_t id : {raster.ids[i], pass.frame.hits[i].primitiveId}) {
              if (id == 0 || !ownConvention) continue;
              // A mesh's triangle, or the buoy (an analytic sphere).
              const PrimitiveIdTable::Decoded decoded = ids.decode(id);
              ASSERT_TRUE(decoded.object >= 0 || decoded.analytic >= 0) << id;
              const std::string& name =
                  decoded.object >= 0
                      ? scene.objects[static_cast<std::size_t>(decoded.object)].name
                      : scene.primitives[static_cast<std::size_t>(decoded.analytic)].name;
              EXPECT_NE(name, "submerged") << x << ", " << y;
              EXPECT_NE(name, "sea_floor") << x << ", " << y;
            }
          }
        }
        // Float32 too: the crate's bottom lies in the water, the oblique near plane, where ZO's
        // window depth is ~1e-17 and finer than the double hit point (its error term in the
        // tolerance model, ScreenPolygons.cpp).
        for (const DepthFormat format : {DepthFormat::Unorm24, DepthFormat::Float32}) {
          const RunRecord run =
              engine::rasterAndCompare(renderer(), pass, format, vertexMode, false);
          EXPECT_TRUE(run.metrics.consistent()) << describe(run);
          EXPECT_GT(run.metrics.rasterHits, 0);
        }
      }
      // The horizon crosses the image: its top 77 of 240 rows look down, away from the water.
      // (Under the other convention the other near plane has another horizon.)
      if (ownConvention) {
        EXPECT_EQ(noRay, 77 * 320);
      }
    }
  }
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
  EXPECT_EQ(info.backend, testing::glBackendForTests());
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_GE(info.subpixelBits, 4);  // the GL spec's minimum
  EXPECT_GE(renderer().maxViewport().width, 4096);
}

}  // namespace
}  // namespace clipray

// The comparison without GL: a raster frame synthesized from the exact analytic answer is
// consistent; each kind of disagreement lands in its class.

#include <gtest/gtest.h>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/math/Projections.hpp"
#include "support/TestScenes.hpp"

namespace clipray {
namespace {

struct Fixture {
  Scene scene;
  PickingCamera camera;
  RasterSetup setup;
  std::optional<SceneIntersector> intersector;
  AnalyticFrame analytic;
  RasterFrame raster;

  explicit Fixture(Viewport viewport, DepthFormat format = DepthFormat::Float32) {
    // A quad whose left edge projects exactly onto clip x = 0 (camera on the z axis, edge at x =
    // 0).
    scene.objects.push_back(testing::quad("quad", {0, -1, 0}, {2, -1, 0}, {2, 1, 0}, {0, 1, 0}));
    camera.mode = kZeroToOne;
    camera.viewport = viewport;
    camera.clipFromWorld =
        perspectiveClipFromView(glm::radians(60.0), 1.0, 0.1, 100.0, kZeroToOne) *
        viewFromWorldLookAt({0, 0, 3}, {0, 0, 0}, {0, 1, 0});
    setup.clipFromWorld = camera.clipFromWorld;
    setup.mode = camera.mode;
    setup.depthFormat = format;
    setup.subpixelBits = 8;
    intersector.emplace(scene, glm::dvec3(0, 0, 2.9));
    analytic = generateRobustRays(camera, 1);
    intersectFrame(analytic, *intersector, 1);
    // The raster a perfect rasterizer would produce: the analytic depth rounded to float.
    raster.viewport = viewport;
    for (std::size_t i = 0; i < analytic.hits.size(); ++i) {
      const Hit& hit = analytic.hits[i];
      raster.ids.push_back(hit.primitiveId);
      if (!hit.hit()) {
        raster.depth.push_back(1.0f);
        continue;
      }
      const glm::dvec4 c =
          camera.clipFromWorld *
          glm::dvec4(analytic.rays[i].origin + hit.t * analytic.rays[i].direction, 1.0);
      raster.depth.push_back(
          static_cast<float>(windowDepthFromNdc(c.z / c.w, DepthConvention::ZeroToOne)));
    }
  }
  ComparisonResult compare() const {
    return compareFrames(raster, analytic, *intersector, setup, 1);
  }
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * camera.viewport.width + x;
  }
};

TEST(Compare, ExactRasterIsConsistent) {
  const Fixture f({33, 21});
  const RunMetrics m = f.compare().metrics;
  EXPECT_TRUE(m.consistent());
  EXPECT_EQ(m.pixels, 33 * 21);
  EXPECT_EQ(m.rasterHits, m.rayHits);
  EXPECT_EQ(m.depthCompared, m.rayHits);
  EXPECT_EQ(m.coverageMismatch.total, 0);
  EXPECT_EQ(m.idMismatch.total, 0);
  // Rounding to float is at most half an ulp: half a quantum of 32F.
  EXPECT_LE(m.depthErrorQuanta.max, 0.5);
  EXPECT_LT(m.toleranceRatio.max, 1.0);
}

TEST(Compare, CoverageMismatchAwayFromEdgesIsUnexplained) {
  Fixture f({33, 21});
  const std::size_t inside = f.index(25, 10);
  ASSERT_NE(f.raster.ids[inside], 0u);
  f.raster.ids[inside] = 0;
  const ComparisonResult r = f.compare();
  EXPECT_EQ(r.metrics.coverageMismatch.total, 1);
  EXPECT_EQ(r.metrics.coverageMismatch.unexplained, 1);
  EXPECT_EQ(r.pixels.classes[inside], PixelClass::CoverageUnexplained);
  EXPECT_FALSE(r.metrics.consistent());
}

TEST(Compare, CoverageMismatchOnAnEdgeIsAmbiguous) {
  // Odd width: pixel 16's centre is clip x = 0, exactly on the quad's left edge.
  Fixture f({33, 21});
  const std::size_t onEdge = f.index(16, 10);
  f.raster.ids[onEdge] = f.raster.ids[onEdge] == 0 ? f.raster.ids[f.index(20, 10)] : 0;
  const ComparisonResult r = f.compare();
  EXPECT_EQ(r.metrics.coverageMismatch.edgeAmbiguous, 1);
  EXPECT_EQ(r.metrics.coverageMismatch.unexplained, 0);
  EXPECT_EQ(r.pixels.classes[onEdge], PixelClass::CoverageEdgeAmbiguous);
  EXPECT_TRUE(r.metrics.consistent());
}

TEST(Compare, DepthErrorBeyondThePredictedToleranceIsReported) {
  Fixture f({33, 21});
  const std::size_t inside = f.index(25, 10);
  // A quad seen head-on has no depth gradient; its tolerance is a few float ulps of d ~ 0.97.
  f.raster.depth[inside] += 1e-4f;
  const ComparisonResult r = f.compare();
  EXPECT_EQ(r.metrics.depthBeyondTolerance, 1);
  EXPECT_EQ(r.pixels.classes[inside], PixelClass::DepthBeyondTolerance);
  EXPECT_GT(r.metrics.toleranceRatio.max, 10.0);
  EXPECT_FALSE(r.metrics.consistent());
}

TEST(Compare, CoarserDepthFormatsGetLargerTolerances) {
  const Fixture f({9, 9});
  ToleranceModel model16(*f.intersector,
                         RasterSetup{f.setup.clipFromWorld, f.setup.mode, DepthFormat::Unorm16},
                         f.camera.viewport);
  ToleranceModel model24(*f.intersector,
                         RasterSetup{f.setup.clipFromWorld, f.setup.mode, DepthFormat::Unorm24},
                         f.camera.viewport);
  const glm::dvec3 hit(1.0, 0.0, 0.0);
  // The difference between the two is exactly the difference of their storage quanta.
  EXPECT_DOUBLE_EQ(model16.depthTolerance(1, hit) - model24.depthTolerance(1, hit),
                   std::ldexp(1.0, -16) - std::ldexp(1.0, -24));
}

}  // namespace
}  // namespace clipray

// The comparison without GL: a raster frame synthesized from the exact analytic answer is
// consistent; each kind of disagreement lands in its class.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/scene/Terrain.hpp"
#include "clipray/util/Check.hpp"
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

TEST(Compare, BackgroundPixelsShowNoDepthWhereverTheyLie) {
  // A run of 64 pixels that shows nothing is written at once; a background pixel beside the quad
  // in a run that shows it goes through the per-pixel loop. Both must read as background: no
  // depth on either side, no ratio.
  const Fixture f({133, 47});
  const ComparisonResult r = f.compare();
  for (const auto& [x, y] : {std::pair(0, 40), std::pair(63, 40), std::pair(10, 20),
                             std::pair(64, 20), std::pair(65, 20), std::pair(100, 45)}) {
    const std::size_t i = f.index(x, y);
    ASSERT_EQ(f.raster.ids[i], 0u) << x << ", " << y;
    ASSERT_FALSE(f.analytic.hits[i].hit()) << x << ", " << y;
    EXPECT_EQ(r.pixels.classes[i], PixelClass::Background) << x << ", " << y;
    EXPECT_TRUE(std::isnan(r.pixels.analyticDepth[i])) << x << ", " << y;
    EXPECT_TRUE(std::isnan(r.pixels.rasterDepth[i])) << x << ", " << y;
    EXPECT_TRUE(std::isnan(r.pixels.toleranceRatio[i])) << x << ", " << y;
  }
  // Beside them in the same run, the quad's pixels are compared.
  EXPECT_EQ(r.pixels.classes[f.index(100, 20)], PixelClass::Agree);
  EXPECT_EQ(r.metrics.pixels, 133 * 47);
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

TEST(Compare, AnIdNoPrimitiveHasIsUnexplained) {
  // A renderer bug: ids past the scene's primitives (the largest 32-bit one too). Nothing explains
  // them, and no table indexed by id is read or written at them (the sanitizer build checks).
  Fixture f({33, 21});
  const std::size_t inside = f.index(25, 10), background = f.index(2, 2);
  ASSERT_NE(f.raster.ids[inside], 0u);
  ASSERT_EQ(f.raster.ids[background], 0u);
  f.raster.ids[inside] = f.intersector->primitiveIdCount() + 7;
  f.raster.ids[background] = 0xffffffffu;
  const ComparisonResult r = f.compare();
  EXPECT_EQ(r.metrics.coverageMismatch.total, 2);
  EXPECT_EQ(r.metrics.coverageMismatch.unexplained, 2);
  EXPECT_EQ(r.pixels.classes[inside], PixelClass::CoverageUnexplained);
  EXPECT_EQ(r.pixels.classes[background], PixelClass::CoverageUnexplained);
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
  const auto setupWith = [&](DepthFormat format) {
    RasterSetup setup;
    setup.clipFromWorld = f.setup.clipFromWorld;
    setup.mode = f.setup.mode;
    setup.depthFormat = format;
    return setup;
  };
  ToleranceModel model16(*f.intersector, setupWith(DepthFormat::Unorm16), f.camera.viewport);
  ToleranceModel model24(*f.intersector, setupWith(DepthFormat::Unorm24), f.camera.viewport);
  const glm::dvec3 hit(1.0, 0.0, 0.0);
  // The difference between the two is exactly the difference of their storage quanta.
  EXPECT_DOUBLE_EQ(model16.depthTolerance(1, hit) - model24.depthTolerance(1, hit),
                   std::ldexp(1.0, -16) - std::ldexp(1.0, -24));
}

bool sameBits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

// The three overall distributions of two runs hold the same bits.
void expectSameDistributions(const RunMetrics& x, const RunMetrics& y) {
  for (const auto& [a, b] : {std::pair(x.depthErrorQuanta, y.depthErrorQuanta),
                             std::pair(x.distanceRelError, y.distanceRelError),
                             std::pair(x.toleranceRatio, y.toleranceRatio)}) {
    EXPECT_TRUE(sameBits(a.max, b.max));
    EXPECT_TRUE(sameBits(a.p50, b.p50));
    EXPECT_TRUE(sameBits(a.p99, b.p99));
  }
}

TEST(Compare, RobustRaysByRowsAreTheRaysOfEachPixel) {
  // generateRobustRays hoists per-row terms and computes directions in blocks, four pixels per
  // instruction where the CPU can: each ray must still be generateForPixel's, bit for bit (a width
  // that is not a multiple of the block nor of four), with the row kernels and without.
  const Viewport viewport{131, 23};
  const glm::dmat4 view = viewFromWorldLookAt({1, 2, 3}, {0, 0, 0}, {0, 1, 0});
  const struct {
    glm::dmat4 clipFromView;
    DepthMode mode;
  } cameras[] = {
      {perspectiveClipFromView(glm::radians(50.0), 1.7, 0.1, 100.0, kZeroToOne), kZeroToOne},
      {perspectiveClipFromView(glm::radians(50.0), 1.7, 0.1, std::nullopt, kZeroToOneReversed),
       kZeroToOneReversed},
      {perspectiveClipFromView(glm::radians(80.0), 0.5, 0.01, 1e4, kNegativeOneToOne),
       kNegativeOneToOne},
      {orthographicClipFromView(-2, 3, -1, 1, 0.5, 20.0, kZeroToOne), kZeroToOne},
      // A reversed-Z matrix drawn under NO: z = -1 lies behind the eye, so no pixel has a ray.
      {perspectiveClipFromView(glm::radians(50.0), 1.7, 0.1, 100.0, kZeroToOneReversed),
       kNegativeOneToOne},
  };
  int withoutRay = 0;
  for (const bool rowKernels : {true, false}) {
    RobustRayGenerator::allowRowKernels(rowKernels);
    for (const auto& c : cameras) {
      PickingCamera camera;
      camera.clipFromWorld = c.clipFromView * view;
      camera.mode = c.mode;
      camera.viewport = viewport;
      const RobustRayGenerator generator(camera.clipFromWorld, camera.mode);
      const AnalyticFrame frame = generateRobustRays(camera, 2);
      ASSERT_EQ(frame.rays.size(), std::size_t{131} * 23);
      // Pieces of rows as a frame's tiles and rows compute them (any start, any length).
      const PixelCentreRays pixelCentreRays(camera.clipFromWorld, camera.mode, viewport);
      std::vector<Ray> piece(viewport.width);
      for (const auto& [x0, count] : {std::pair(0, 131), std::pair(8, 8), std::pair(125, 6),
                                      std::pair(3, 1), std::pair(61, 67)}) {
        for (int y = 0; y < viewport.height; y += 5) {
          pixelCentreRays.row(y, x0, count, piece.data());
          for (int k = 0; k < count; ++k) {
            const Ray expected = generator.generateForPixel(x0 + k, y, viewport);
            ASSERT_EQ(std::memcmp(&expected, &piece[k], sizeof(Ray)), 0)
                << "piece at " << x0 << " of " << count << ", pixel " << x0 + k << ", " << y;
          }
        }
      }
      for (int y = 0; y < viewport.height; ++y) {
        for (int x = 0; x < viewport.width; ++x) {
          const Ray expected = generator.generateForPixel(x, y, viewport);
          const Ray& got = frame.rays[static_cast<std::size_t>(y) * viewport.width + x];
          ASSERT_EQ(std::memcmp(&expected, &got, sizeof(Ray)), 0)
              << "pixel " << x << ", " << y << (rowKernels ? " (row kernels)" : " (portable)");
          withoutRay += got.tMax == kNoRayTMax ? 1 : 0;
        }
      }
    }
  }
  RobustRayGenerator::allowRowKernels(true);
  EXPECT_EQ(withoutRay, 2 * 131 * 23);  // the last camera's pixels, with both paths
}

TEST(Compare, ToleranceModelOfSomeIdsAnswersAsTheFullModel) {
  // compareFrames clips only the triangles the frames show; asked about any other primitive
  // the model must still answer what the model of every triangle answers.
  Fixture f({17, 13});
  f.scene.objects.push_back(
      testing::quad("far quad", {-3, -1, -2}, {-1, -1, -2}, {-1, 1, -2}, {-3, 1, -2}));
  f.scene.objects.push_back(  // partly behind the camera: clipped by the near plane
      testing::quad("crossing", {-1, -2, 5}, {1, -2, 5}, {1, -2, -5}, {-1, -2, -5}));
  AnalyticPrimitive sphere;
  sphere.kind = PrimitiveKind::Sphere;
  sphere.worldFromLocal = glm::dmat4(0.5);
  sphere.worldFromLocal[3] = glm::dvec4(1.5, 0.5, -1.0, 1.0);
  sphere.localFromWorld = glm::inverse(sphere.worldFromLocal);
  f.scene.primitives.push_back(sphere);
  const SceneIntersector intersector(f.scene, glm::dvec3(0, 0, 2.9));
  const ToleranceModel full(intersector, f.setup, f.camera.viewport);
  const std::uint32_t some[] = {2, 5};
  const ToleranceModel partial(intersector, f.setup, f.camera.viewport, some, 2);
  const RobustRayGenerator rays(f.setup.clipFromWorld, f.setup.mode);
  for (std::uint32_t id = 1; id <= intersector.primitiveIdCount(); ++id) {
    for (const glm::dvec2 pixel : {glm::dvec2(0.5, 0.5), glm::dvec2(8.5, 6.5),
                                   glm::dvec2(12.25, 3.75), glm::dvec2(16.5, 12.5)}) {
      SCOPED_TRACE(::testing::Message() << "id " << id << " at " << pixel.x << ", " << pixel.y);
      EXPECT_EQ(full.edgeAmbiguous(id, pixel), partial.edgeAmbiguous(id, pixel));
      EXPECT_TRUE(sameBits(full.surfaceDepthAt(id, pixel), partial.surfaceDepthAt(id, pixel)));
      EXPECT_TRUE(
          sameBits(full.surfaceToleranceAt(id, pixel), partial.surfaceToleranceAt(id, pixel)));
      if (intersector.isAnalytic(id)) continue;
      EXPECT_TRUE(
          sameBits(full.edgeDistancePixels(id, pixel), partial.edgeDistancePixels(id, pixel)));
      EXPECT_EQ(full.insidePolygon(id, pixel), partial.insidePolygon(id, pixel));
      EXPECT_TRUE(sameBits(full.edgeEpsilonPixels(id), partial.edgeEpsilonPixels(id)));
      EXPECT_TRUE(sameBits(full.planeDepthAt(id, pixel), partial.planeDepthAt(id, pixel)));
      const glm::dvec3 hit(0.25 * id, 0.5, -0.125 * id);
      EXPECT_TRUE(sameBits(full.depthTolerance(id, hit), partial.depthTolerance(id, hit)));
      EXPECT_TRUE(
          sameBits(full.depthTolerance(id, hit),
                   partial.depthToleranceAtClip(id, f.setup.clipFromWorld * glm::dvec4(hit, 1.0))));
    }
  }
}

TEST(Compare, ModelsAskedInTurnAboutIdsNotBuiltUpFrontEachAnswerTheirOwn) {
  // Ids not built up front are built when asked and kept in the asking thread's cache: two
  // models of other cameras asked in turn on one thread, and models made one after another in
  // the same place, must each answer as their full model does, never with another's polygon.
  Fixture f({17, 13});
  f.scene.objects.push_back(
      testing::quad("far quad", {-3, -1, -2}, {-1, -1, -2}, {-1, 1, -2}, {-3, 1, -2}));
  // Over a thousand triangles: ids that share a cache entry.
  f.scene.objects.push_back(makeTerrainMesh(2500, 7, "terrain"));
  const SceneIntersector intersector(f.scene, glm::dvec3(0, 0, 2.9));
  ASSERT_GT(intersector.primitiveIdCount(), 2048u);
  RasterSetup other = f.setup;
  other.clipFromWorld = perspectiveClipFromView(glm::radians(40.0), 1.0, 0.1, 100.0, kZeroToOne) *
                        viewFromWorldLookAt({0.5, 0.25, 4}, {0, 0, 0}, {0, 1, 0});
  const ToleranceModel fullA(intersector, f.setup, f.camera.viewport);
  const ToleranceModel fullB(intersector, other, f.camera.viewport);
  const auto sameAnswers = [&](const ToleranceModel& full, const ToleranceModel& lazy,
                               std::uint32_t id) {
    for (const glm::dvec2 pixel : {glm::dvec2(0.5, 0.5), glm::dvec2(8.5, 6.5)}) {
      EXPECT_TRUE(sameBits(full.edgeDistancePixels(id, pixel), lazy.edgeDistancePixels(id, pixel)));
      EXPECT_TRUE(sameBits(full.planeDepthAt(id, pixel), lazy.planeDepthAt(id, pixel)));
    }
    EXPECT_TRUE(sameBits(full.edgeEpsilonPixels(id), lazy.edgeEpsilonPixels(id)));
    const glm::dvec3 hit(0.25 * id, 0.5, -0.125 * id);
    EXPECT_TRUE(sameBits(full.depthTolerance(id, hit), lazy.depthTolerance(id, hit)));
  };
  {
    const ToleranceModel lazyA(intersector, f.setup, f.camera.viewport, {}, 1);
    const ToleranceModel lazyB(intersector, other, f.camera.viewport, {}, 1);
    for (int pass = 0; pass < 2; ++pass) {  // the second pass reads the cache
      for (std::uint32_t id = 1; id <= intersector.primitiveIdCount(); ++id) {
        SCOPED_TRACE(::testing::Message() << "pass " << pass << " id " << id);
        sameAnswers(fullA, lazyA, id);
        sameAnswers(fullB, lazyB, id);
      }
    }
  }
  for (int k = 0; k < 4; ++k) {
    const RasterSetup& setup = k % 2 == 0 ? f.setup : other;
    const ToleranceModel lazy(intersector, setup, f.camera.viewport, {}, 1);
    for (std::uint32_t id = 1; id <= intersector.primitiveIdCount(); ++id) {
      SCOPED_TRACE(::testing::Message() << "model " << k << " id " << id);
      sameAnswers(k % 2 == 0 ? fullA : fullB, lazy, id);
    }
    // Ids no triangle has have no polygon, whatever the cache holds from the ids above.
    for (const std::uint32_t none : {0u, intersector.primitiveIdCount() + 1, 0xffffffffu}) {
      EXPECT_EQ(lazy.edgeDistancePixels(none, {8.5, 6.5}), std::numeric_limits<double>::infinity())
          << none;
      EXPECT_FALSE(lazy.insidePolygon(none, {8.5, 6.5})) << none;
    }
  }
}

TEST(Compare, ARasterThatDrawsNothingHasEveryRayPixelJudgedByItsOwnPolygon) {
  // Every id then shows on the ray side only (none is built up front): each hit pixel is a
  // coverage mismatch, edge-ambiguous exactly where the model of every triangle says so.
  Fixture f({61, 47});
  f.scene.objects.push_back(
      testing::quad("second", {-2, -1, -1}, {-0.5, -1, -1}, {-0.5, 0.5, -1}, {-2, 0.5, -1}));
  f.intersector.emplace(f.scene, glm::dvec3(0, 0, 2.9));
  intersectFrame(f.analytic, *f.intersector, 1);
  std::fill(f.raster.ids.begin(), f.raster.ids.end(), 0u);
  std::fill(f.raster.depth.begin(), f.raster.depth.end(), 1.0f);
  for (const unsigned threads : {1u, 2u}) {
    const ComparisonResult r =
        compareFrames(f.raster, f.analytic, *f.intersector, f.setup, threads);
    const ToleranceModel full(*f.intersector, f.setup, f.camera.viewport);
    std::int64_t rayPixels = 0, ambiguous = 0;
    for (int y = 0; y < 47; ++y) {
      for (int x = 0; x < 61; ++x) {
        const std::size_t i = f.index(x, y);
        const std::uint32_t id = f.analytic.hits[i].primitiveId;
        if (id == 0) {
          EXPECT_EQ(r.pixels.classes[i], PixelClass::Background);
          continue;
        }
        ++rayPixels;
        const bool edge = full.edgeAmbiguous(id, {x + 0.5, y + 0.5});
        ambiguous += edge ? 1 : 0;
        EXPECT_EQ(r.pixels.classes[i],
                  edge ? PixelClass::CoverageEdgeAmbiguous : PixelClass::CoverageUnexplained)
            << x << ", " << y;
      }
    }
    EXPECT_GT(rayPixels, 500);
    EXPECT_GT(ambiguous, 0);
    EXPECT_EQ(r.metrics.coverageMismatch.total, rayPixels);
    EXPECT_EQ(r.metrics.coverageMismatch.edgeAmbiguous, ambiguous);
    EXPECT_EQ(r.metrics.depthCompared, 0);
  }
}

TEST(Compare, FiguresDoNotDependOnTheThreadCount) {
  // Samples are gathered per worker and their distributions read where they lie: any split of
  // the rows gives the same figures.
  Fixture f({61, 47});
  for (std::size_t i = 0; i < f.raster.depth.size(); i += 7) {
    if (f.raster.ids[i] != 0) f.raster.depth[i] = std::nextafter(f.raster.depth[i], 2.0f);
  }
  const RunMetrics one = compareFrames(f.raster, f.analytic, *f.intersector, f.setup, 1).metrics;
  const RunMetrics three = compareFrames(f.raster, f.analytic, *f.intersector, f.setup, 3).metrics;
  EXPECT_EQ(one.depthCompared, three.depthCompared);
  expectSameDistributions(one, three);
  ASSERT_EQ(one.byKind.size(), 1u);
  EXPECT_TRUE(sameBits(one.byKind[0].toleranceRatio.p99, one.toleranceRatio.p99));
  // Every seventh depth moved by one float ulp: the largest error is about a whole quantum.
  EXPECT_GT(one.depthErrorQuanta.max, 0.5);
}

TEST(Compare, RaysComputedPerRowGiveTheStoredRaysFigures) {
  // A reconcile compares a robustRayFrame, whose rays are computed row by row where the compare
  // reads them: every figure and every image must be the stored rays' (the same bits), with
  // pixels of every class (moved depths, a missing raster pixel, an edge, an id past the scene).
  // 133 wide: three runs of 64 pixels per row. The quad covers columns 66-132 of rows 10-36.
  Fixture f({133, 47});
  for (std::size_t i = 0; i < f.raster.depth.size(); i += 5) {
    if (f.raster.ids[i] != 0) f.raster.depth[i] = std::nextafter(f.raster.depth[i], 2.0f);
  }
  ASSERT_NE(f.raster.ids[f.index(100, 20)], 0u);
  ASSERT_EQ(f.raster.ids[f.index(20, 40)], 0u);
  f.raster.depth[f.index(100, 20)] += 1e-4f;
  f.raster.ids[f.index(110, 30)] = 0;
  f.raster.ids[f.index(67, 12)] = f.raster.ids[f.index(67, 12)] == 0 ? 1 : 0;
  f.raster.ids[f.index(20, 40)] = 99;  // an id past the scene, in a run that shows nothing else
  // A run whose pixels only the rays show (the raster has none there): their rays are needed.
  for (int x = 64; x < 128; ++x) f.raster.ids[f.index(x, 25)] = 0;
  AnalyticFrame computed = robustRayFrame(f.camera);
  intersectFrame(computed, *f.intersector, f.camera, 2);
  for (const unsigned threads : {1u, 2u}) {
    const ComparisonResult a =
        compareFrames(f.raster, f.analytic, *f.intersector, f.setup, threads);
    const ComparisonResult b = compareFrames(f.raster, computed, *f.intersector, f.setup, threads);
    const RunMetrics &x = a.metrics, &y = b.metrics;
    EXPECT_EQ(x.rayHits, y.rayHits);
    EXPECT_EQ(x.depthCompared, y.depthCompared);
    EXPECT_EQ(x.depthBeyondTolerance, y.depthBeyondTolerance);
    EXPECT_EQ(x.coverageMismatch.total, y.coverageMismatch.total);
    EXPECT_EQ(x.coverageMismatch.unexplained, y.coverageMismatch.unexplained);
    EXPECT_EQ(x.idMismatch.total, y.idMismatch.total);
    expectSameDistributions(x, y);
    const auto sameBytes = [](const auto& u, const auto& v) {
      return u.size() == v.size() && std::memcmp(u.data(), v.data(), u.size() * sizeof(u[0])) == 0;
    };
    EXPECT_TRUE(sameBytes(a.pixels.analyticDepth, b.pixels.analyticDepth));
    EXPECT_TRUE(sameBytes(a.pixels.rasterDepth, b.pixels.rasterDepth));
    EXPECT_TRUE(sameBytes(a.pixels.toleranceRatio, b.pixels.toleranceRatio));
    EXPECT_TRUE(sameBytes(a.pixels.classes, b.pixels.classes));
    EXPECT_EQ(x.depthBeyondTolerance, 1);  // the moved pixel; the ulp moves stay within tolerance
    EXPECT_GE(x.coverageMismatch.unexplained, 2);
  }
  // A frame with neither stored nor computed rays is refused.
  AnalyticFrame none;
  none.viewport = f.camera.viewport;
  none.hits = computed.hits;
  EXPECT_THROW(compareFrames(f.raster, none, *f.intersector, f.setup, 1), InternalError);
}

TEST(Compare, ToleranceRatiosAreTheToleranceModelsOwn) {
  // compareFrames evaluates the triangle tolerance in its loop (sharing the hit's depth and depth
  // quantum with the pixel's figures): each ratio is error / depthToleranceAtClip, bit for bit,
  // in every depth format.
  for (const DepthFormat format :
       {DepthFormat::Float32, DepthFormat::Unorm24, DepthFormat::Unorm16}) {
    Fixture f({61, 47}, format);
    for (std::size_t i = 0; i < f.raster.depth.size(); i += 5) {
      if (f.raster.ids[i] != 0) f.raster.depth[i] = std::nextafter(f.raster.depth[i], 2.0f);
    }
    const ComparisonResult r = f.compare();
    const ToleranceModel model(*f.intersector, f.setup, f.camera.viewport);
    int checked = 0;
    for (std::size_t i = 0; i < r.pixels.classes.size(); ++i) {
      const PixelClass cls = r.pixels.classes[i];
      if (cls != PixelClass::Agree && cls != PixelClass::DepthBeyondTolerance) continue;
      const Ray& ray = f.analytic.rays[i];
      const Hit& hit = f.analytic.hits[i];
      const glm::dvec4 clip =
          f.setup.clipFromWorld * glm::dvec4(ray.origin + hit.t * ray.direction, 1.0);
      const double error =
          std::abs(static_cast<double>(f.raster.depth[i]) - r.pixels.analyticDepth[i]);
      const float ratio =
          static_cast<float>(error / model.depthToleranceAtClip(hit.primitiveId, clip));
      EXPECT_EQ(std::bit_cast<std::uint32_t>(r.pixels.toleranceRatio[i]),
                std::bit_cast<std::uint32_t>(ratio));
      ++checked;
    }
    EXPECT_GT(checked, 100);
  }
}

TEST(Compare, NaNRasterDepthIsBeyondTolerance) {
  // A NaN sample takes the distributions' general path (no bit-pattern ordering for NaN).
  Fixture f({33, 21});
  const std::size_t inside = f.index(25, 10);
  f.raster.depth[inside] = std::numeric_limits<float>::quiet_NaN();
  const ComparisonResult r = f.compare();
  EXPECT_EQ(r.metrics.depthBeyondTolerance, 1);
  EXPECT_EQ(r.pixels.classes[inside], PixelClass::DepthBeyondTolerance);
  EXPECT_EQ(r.metrics.depthCompared, r.metrics.rayHits);
}

}  // namespace
}  // namespace clipray

namespace clipray {
namespace {

bool sameFigures(const Distribution& a, const Distribution& b) {
  return std::bit_cast<std::uint64_t>(a.max) == std::bit_cast<std::uint64_t>(b.max) &&
         std::bit_cast<std::uint64_t>(a.p50) == std::bit_cast<std::uint64_t>(b.p50) &&
         std::bit_cast<std::uint64_t>(a.p99) == std::bit_cast<std::uint64_t>(b.p99);
}

TEST(Compare, AModelBuiltForOneDepthFormatAnswersForAnotherRasterAsItsOwnWould) {
  // The model of a raster that shows only the first quad serves a 16-bit raster that shows the
  // second quad too (its polygons then come from the thread's cache): the same classes, depths
  // and figures as the model compareFrames builds for that raster itself.
  Fixture f({61, 47});
  f.scene.objects.push_back(
      testing::quad("second", {-2, -1, -1}, {-0.5, -1, -1}, {-0.5, 0.5, -1}, {-2, 0.5, -1}));
  f.intersector.emplace(f.scene, glm::dvec3(0, 0, 2.9));
  intersectFrame(f.analytic, *f.intersector, 1);
  RasterFrame firstOnly = f.raster;  // the first quad's pixels only (the Fixture's raster)
  RasterFrame both = f.raster;
  for (std::size_t i = 0; i < both.ids.size(); ++i) {
    const Hit& hit = f.analytic.hits[i];
    both.ids[i] = hit.primitiveId;
    if (!hit.hit()) continue;
    const glm::dvec4 c =
        f.camera.clipFromWorld *
        glm::dvec4(f.analytic.rays[i].origin + hit.t * f.analytic.rays[i].direction, 1.0);
    const double depth = windowDepthFromNdc(c.z / c.w, DepthConvention::ZeroToOne);
    both.depth[i] = static_cast<float>(std::round(depth * 65535.0) / 65535.0);
  }
  ASSERT_EQ(std::count_if(firstOnly.ids.begin(), firstOnly.ids.end(),
                          [](std::uint32_t id) { return id > 2; }),
            0);  // the second quad's ids, 3 and 4, are not in it
  ASSERT_GT(
      std::count_if(both.ids.begin(), both.ids.end(), [](std::uint32_t id) { return id > 2; }),
      100);
  const std::unique_ptr<ToleranceModel> model =
      toleranceModelOfRaster(firstOnly, *f.intersector, f.setup, 2);
  RasterSetup setup16 = f.setup;
  setup16.depthFormat = DepthFormat::Unorm16;
  // Until it is told the other format, it answers for another setup and is refused.
  EXPECT_THROW(compareFrames(both, f.analytic, *f.intersector, setup16, *model, 2), InternalError);
  model->useDepthFormat(DepthFormat::Unorm16);
  const ComparisonResult shared =
      compareFrames(both, f.analytic, *f.intersector, setup16, *model, 2);
  const ComparisonResult own = compareFrames(both, f.analytic, *f.intersector, setup16, 2);
  EXPECT_GT(own.metrics.depthCompared, 61 * 47 / 4);
  EXPECT_EQ(shared.metrics.depthCompared, own.metrics.depthCompared);
  EXPECT_EQ(shared.metrics.depthBeyondTolerance, own.metrics.depthBeyondTolerance);
  EXPECT_EQ(shared.metrics.coverageMismatch.total, own.metrics.coverageMismatch.total);
  EXPECT_TRUE(sameFigures(shared.metrics.toleranceRatio, own.metrics.toleranceRatio));
  EXPECT_TRUE(sameFigures(shared.metrics.depthErrorQuanta, own.metrics.depthErrorQuanta));
  EXPECT_TRUE(sameFigures(shared.metrics.distanceRelError, own.metrics.distanceRelError));
  for (std::size_t i = 0; i < both.ids.size(); ++i) {
    ASSERT_EQ(shared.pixels.classes[i], own.pixels.classes[i]) << i;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(shared.pixels.toleranceRatio[i]),
              std::bit_cast<std::uint32_t>(own.pixels.toleranceRatio[i]))
        << i;
  }
}

}  // namespace
}  // namespace clipray

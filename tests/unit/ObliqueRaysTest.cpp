// Oblique near planes (Lengyel's clip-plane trick) with the horizon in view: a water reflection
// pass. The pixels whose line of sight meets the water plane only behind the eye have no ray, in
// the robust generator (double, reconcile), in the bench's robust kernels (float and double) and in
// the reference; the other pixels keep the rays a plain camera with the same view gives; the
// compare calls a raster hit where no ray exists unexplained coverage.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/rays/QuadReference.hpp"
#include "clipray/rays/RayErrors.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "support/TestScenes.hpp"

namespace clipray {
namespace {

constexpr Viewport kViewport{64, 48};

// The water reflection camera of scenes/water_reflection.json: the view from (0, 3, 12) towards
// (0, 0.5, 0) mirrored in the water plane y = 0 (optionally without the mirror: the eye below the
// water looking up), a GL perspective (fov 60, near 0.1, far 1000) built for `mode`, column
// vectors, p_clip = clipFromWorld * p_world.
struct WaterCamera {
  glm::dmat4 viewFromWorld;
  glm::dmat4 plainClipFromView;  // the projection before Lengyel's change of row 2
  glm::dmat4 clipFromWorld;      // Lengyel's oblique projection (near plane = water) * view
  glm::dmat4 plainClipFromWorld;
};

// Lengyel, "Oblique View Frustum Depth Projection and Clipping" (2005): row 2 := (2 / C.q) C -
// row 3 for NO, (1 / C.q) C for ZO, q the far corner P^-1 (sgn C'x, sgn C'y, 1, 1), C' = P^-T C.
glm::dmat4 lengyel(glm::dmat4 projection, const glm::dvec4& viewPlane, DepthMode mode) {
  auto sign = [](double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); };
  const glm::dmat4 inverse = glm::inverse(projection);
  const glm::dvec4 clipPlane = glm::transpose(inverse) * viewPlane;
  const glm::dvec4 q = inverse * glm::dvec4(sign(clipPlane.x), sign(clipPlane.y), 1.0, 1.0);
  const bool zo = mode.convention == DepthConvention::ZeroToOne;
  const double scale = (zo ? 1.0 : 2.0) / glm::dot(viewPlane, q);
  for (int column = 0; column < 4; ++column) {
    projection[column][2] = viewPlane[column] * scale - (zo ? 0.0 : projection[column][3]);
  }
  return projection;
}

WaterCamera waterCamera(DepthMode mode, bool mirrored = true,
                        glm::dvec4 waterPlane = {0.0, 1.0, 0.0, 0.0}) {
  WaterCamera c;
  if (mirrored) {
    glm::dmat4 mirror(1.0);
    mirror[1][1] = -1.0;  // world y -> -y: the reflection in the water plane
    c.viewFromWorld = viewFromWorldLookAt({0, 3, 12}, {0, 0.5, 0}, {0, 1, 0}) * mirror;
  } else {
    c.viewFromWorld = viewFromWorldLookAt({0, -3, 12}, {0, -0.5, 0}, {0, 1, 0});
  }
  c.plainClipFromView = perspectiveClipFromView(
      glm::radians(60.0), double(kViewport.width) / kViewport.height, 0.1, 1000.0, mode);
  const glm::dvec4 waterInView = glm::transpose(glm::inverse(c.viewFromWorld)) * waterPlane;
  c.clipFromWorld = lengyel(c.plainClipFromView, waterInView, mode) * c.viewFromWorld;
  c.plainClipFromWorld = c.plainClipFromView * c.viewFromWorld;
  return c;
}

// Independent of the generators: the line of sight of pixel (i, j) in world space, pointing away
// from the eye (the view looks down -z), and whether it climbs towards the water from below.
bool climbsToTheWater(const WaterCamera& c, int i, int j) {
  const glm::dvec2 xy = clipXYOfPixelCentre(i, j, kViewport);
  const glm::dvec4 inView(xy.x / c.plainClipFromView[0][0], xy.y / c.plainClipFromView[1][1], -1.0,
                          0.0);
  return (glm::inverse(c.viewFromWorld) * inView).y > 0.0;
}

// 15 of 48 rows look below the horizon (the eye looks up 11.8 deg, fov 60): the bottom ones
// from below the water, the top ones in the mirrored view.
constexpr int kNoRayPixels = 15 * 64;

TEST(ObliqueRays, NoRayExactlyWhereTheLineOfSightNeverReachesTheWaterInFront) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    for (const bool mirrored : {true, false}) {
      SCOPED_TRACE(mode.name() + (mirrored ? " mirrored" : " plain"));
      const WaterCamera c = waterCamera(mode, mirrored);
      const RobustRayGenerator oblique(c.clipFromWorld, mode), plain(c.plainClipFromWorld, mode);
      int without = 0;
      for (int j = 0; j < kViewport.height; ++j) {
        for (int i = 0; i < kViewport.width; ++i) {
          const Ray ray = oblique.generateForPixel(i, j, kViewport);
          const Ray before = plain.generateForPixel(i, j, kViewport);
          if (!climbsToTheWater(c, i, j)) {
            ++without;
            EXPECT_EQ(ray.tMax, kNoRayTMax) << i << ", " << j;
            continue;
          }
          ASSERT_GT(ray.tMax, 0.0) << i << ", " << j;
          // Rows x, y and w are the plain camera's, so is the direction, bit for bit; the
          // origin lies on the water.
          EXPECT_EQ(std::memcmp(&ray.direction, &before.direction, sizeof(glm::dvec3)), 0)
              << i << ", " << j;
          EXPECT_LE(std::abs(ray.origin.y), 1e-12 * glm::length(ray.origin)) << i << ", " << j;
          EXPECT_GT(glm::dot(ray.origin - glm::dvec3(0, -3, 12), ray.direction), 0.0);
        }
      }
      EXPECT_EQ(without, kNoRayPixels);
      // The frame's rows (four pixels per instruction where the CPU can) give the same bits.
      PickingCamera camera{c.clipFromWorld, mode, kViewport};
      for (const bool rowKernels : {true, false}) {
        RobustRayGenerator::allowRowKernels(rowKernels);
        const AnalyticFrame frame = generateRobustRays(camera, 2);
        for (int j = 0; j < kViewport.height; ++j) {
          for (int i = 0; i < kViewport.width; ++i) {
            const Ray expected = oblique.generateForPixel(i, j, kViewport);
            ASSERT_EQ(std::memcmp(&expected, &frame.rays[std::size_t(j) * kViewport.width + i],
                                  sizeof(Ray)),
                      0)
                << i << ", " << j;
          }
        }
      }
      RobustRayGenerator::allowRowKernels(true);
    }
  }
}

TEST(ObliqueRays, TheReferenceAndTheBenchKernelsAgreeOnWhichPixelsHaveNoRay) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    SCOPED_TRACE(mode.name());
    const WaterCamera c = waterCamera(mode);
    CameraInputs inputs;
    inputs.clipFromWorld = c.clipFromWorld;
    inputs.mode = mode;
    const QuadReference floatReference(glm::dmat4(glm::mat4(c.clipFromWorld)), mode, kViewport);
    const QuadReference doubleReference(c.clipFromWorld, mode, kViewport);
    for (const BatchCodePath path : supportedBatchCodePaths()) {
      limitBatchCodePath(path);
      SCOPED_TRACE(batchCodePathName(path));
      const auto robustFloat = makeRayGenerator<float>(RayMethod::Robust, inputs, kViewport);
      const auto robustDouble = makeRayGenerator<double>(RayMethod::Robust, inputs, kViewport);
      const auto twoPoint = makeRayGenerator<float>(RayMethod::TwoPoint, inputs, kViewport);
      ErrorAccumulator floatErrors, doubleErrors, twoPointErrors;
      std::vector<ReferenceRay> floatRow, doubleRow;
      RayBuffer<float> floatRays(kViewport.width), twoPointRays(kViewport.width);
      RayBuffer<double> doubleRays(kViewport.width);
      for (int j = 0; j < kViewport.height; ++j) {
        floatReference.row(j, floatRow);
        doubleReference.row(j, doubleRow);
        for (int i = 0; i < kViewport.width; ++i) {
          EXPECT_EQ(doubleRow[std::size_t(i)].hasRay(), climbsToTheWater(c, i, j));
          EXPECT_EQ(floatRow[std::size_t(i)].hasRay(), climbsToTheWater(c, i, j));
        }
        robustFloat->generateRow(j, floatRays.all());
        robustDouble->generateRow(j, doubleRays.all());
        twoPoint->generateRow(j, twoPointRays.all());
        for (int i = 0; i < kViewport.width; ++i) {
          // The batch is the scalar call, bit for bit, with or without a ray.
          const CameraRay<float> a = robustFloat->pixelRay(i, j), b = floatRays.all().load(i);
          EXPECT_TRUE(a.tMax == b.tMax && a.direction == b.direction) << i << ", " << j;
          EXPECT_EQ(a.tMax < 0.f, !climbsToTheWater(c, i, j)) << i << ", " << j;
          if (a.tMax < 0.f) {
            EXPECT_EQ(a.tMax, -1.f);
          }
        }
        floatErrors.addRow(floatRow, floatRays.all());
        doubleErrors.addRow(doubleRow, doubleRays.all());
        twoPointErrors.addRow(floatRow, twoPointRays.all());
      }
      for (const MethodErrors& e : {floatErrors.result(), doubleErrors.result()}) {
        EXPECT_EQ(e.noRay, std::uint64_t{kNoRayPixels});
        EXPECT_EQ(e.noRayDisagree, 0u);
        EXPECT_EQ(e.rays, std::uint64_t{64 * 48 - kNoRayPixels});
        EXPECT_EQ(e.backward, 0u);
        EXPECT_EQ(e.nonfinite, 0u);
      }
      // two_point has no notion of "no ray": it gives one at every pixel below the horizon.
      EXPECT_EQ(twoPointErrors.result().noRay, std::uint64_t{kNoRayPixels});
      EXPECT_EQ(twoPointErrors.result().noRayDisagree, std::uint64_t{kNoRayPixels});
    }
    limitBatchCodePath(std::nullopt);
  }
}

TEST(ObliqueRays, DescribeProjectionReadsAReflectionCamera) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    for (const bool mirrored : {true, false}) {
      SCOPED_TRACE(mode.name() + (mirrored ? " mirrored" : " plain"));
      const ProjectionCheck check =
          describeProjection(waterCamera(mode, mirrored).clipFromWorld, mode);
      ASSERT_TRUE(check.facts) << check.problem;
      EXPECT_FALSE(check.facts->parallel);
      EXPECT_EQ(check.facts->mirrored, mirrored);
      EXPECT_NEAR(check.facts->fovYDegrees, 60.0, 1e-9);
      EXPECT_NEAR(glm::length(check.facts->eye - glm::dvec3(0, -3, 12)), 0.0, 1e-12);
      // The centre ray climbs 11.8 degrees and meets the water 3 / sin(11.8 deg) from the eye.
      EXPECT_NEAR(check.facts->forward.y, 2.5 / std::sqrt(2.5 * 2.5 + 144.0), 1e-12);
      EXPECT_NEAR(check.facts->nearDistance, 3.0 * std::sqrt(2.5 * 2.5 + 144.0) / 2.5, 1e-9);
    }
  }
  // A reversed-Z matrix drawn under NO: z = -1 lies behind the eye, the eye on the kept side.
  const glm::dmat4 reversed =
      perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 1000.0, kZeroToOneReversed) *
      waterCamera(kZeroToOne).viewFromWorld;
  EXPECT_EQ(describeProjection(reversed, kNegativeOneToOne).problem,
            "not a projection: the near plane lies behind the eye");
  // Looking straight down, away from the water: Lengyel's scale 1 / C.q turns the plane over,
  // and the eye lies on its kept side.
  const glm::dmat4 down = viewFromWorldLookAt({0, -3, 12}, {0, -10, 12}, {0, 0, -1});
  const glm::dmat4 projection =
      perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 1000.0, kZeroToOne);
  const glm::dmat4 away =
      lengyel(projection, glm::transpose(glm::inverse(down)) * glm::dvec4(0, 1, 0, 0), kZeroToOne) *
      down;
  EXPECT_EQ(describeProjection(away, kZeroToOne).problem,
            "not a projection: the near plane lies behind the eye");
}

TEST(ObliqueRays, ARasterHitWhereNoRayExistsIsUnexplainedCoverage) {
  // A wall standing in the water, 20 beyond the mirrored eye: above the water it shows on both
  // sides; below the horizon there is no ray, and a raster hit there is a bug nothing explains.
  const WaterCamera c = waterCamera(kZeroToOne, false);
  Scene scene;
  scene.objects.push_back(
      testing::quad("wall", {-40, -10, -8}, {40, -10, -8}, {40, 30, -8}, {-40, 30, -8}));
  PickingCamera camera{c.clipFromWorld, kZeroToOne, kViewport};
  RasterSetup setup;
  setup.clipFromWorld = camera.clipFromWorld;
  setup.mode = camera.mode;
  setup.depthFormat = DepthFormat::Float32;
  setup.subpixelBits = 8;
  const SceneIntersector intersector(scene, glm::dvec3(0, -3, 12));
  AnalyticFrame analytic = generateRobustRays(camera, 1);
  intersectFrame(analytic, intersector, 1);
  // The raster a perfect rasterizer would produce: the analytic depth rounded to float.
  RasterFrame raster;
  raster.viewport = kViewport;
  int hits = 0;
  for (std::size_t i = 0; i < analytic.hits.size(); ++i) {
    const Hit& hit = analytic.hits[i];
    raster.ids.push_back(hit.primitiveId);
    if (!hit.hit()) {
      raster.depth.push_back(1.0f);
      continue;
    }
    ++hits;
    const Ray& ray = analytic.rays[i];
    const glm::dvec4 p = camera.clipFromWorld * glm::dvec4(ray.origin + hit.t * ray.direction, 1);
    raster.depth.push_back(
        static_cast<float>(windowDepthFromNdc(p.z / p.w, DepthConvention::ZeroToOne)));
  }
  // Pixels above the horizon see the wall, but for the 7 rows just above it: their lines of sight
  // climb less than 3 in 20 and meet the water beyond the wall, whose part in front of that is
  // under water (clipped). None below the horizon does.
  EXPECT_EQ(hits, 64 * 48 - kNoRayPixels - 7 * 64);
  const RunMetrics exact = compareFrames(raster, analytic, intersector, setup, 1).metrics;
  EXPECT_TRUE(exact.consistent());
  EXPECT_EQ(exact.coverageMismatch.total, 0);

  // The bottom-left pixel and one just below the horizon (row 14 of 48) show the wall.
  const std::size_t corner = 0, belowHorizon = std::size_t(14) * 64 + 40;
  ASSERT_EQ(analytic.rays[corner].tMax, kNoRayTMax);
  ASSERT_EQ(analytic.rays[belowHorizon].tMax, kNoRayTMax);
  ASSERT_GT(analytic.rays[belowHorizon + 64].tMax, 0.0);
  for (const std::size_t i : {corner, belowHorizon}) {
    raster.ids[i] = 1;
    raster.depth[i] = 0.5f;
  }
  const ComparisonResult r = compareFrames(raster, analytic, intersector, setup, 1);
  EXPECT_EQ(r.metrics.coverageMismatch.total, 2);
  EXPECT_EQ(r.metrics.coverageMismatch.unexplained, 2);
  EXPECT_EQ(r.metrics.coverageMismatch.edgeAmbiguous, 0);
  EXPECT_EQ(r.pixels.classes[corner], PixelClass::CoverageUnexplained);
  EXPECT_EQ(r.pixels.classes[belowHorizon], PixelClass::CoverageUnexplained);
  EXPECT_FALSE(r.metrics.consistent());
}

}  // namespace
}  // namespace clipray

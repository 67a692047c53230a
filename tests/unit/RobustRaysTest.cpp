#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clipray/math/Projections.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "support/Conditioning.hpp"

namespace clipray {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

glm::dvec3 clipNdc(const glm::dmat4& m, const glm::dvec3& p) {
  const glm::dvec4 c = m * glm::dvec4(p, 1.0);
  return glm::dvec3(c) / c.w;
}

using testing::conditionNumber;

struct CameraCase {
  const char* name;
  glm::dmat4 clipFromWorld;
  DepthMode mode;
};

std::vector<CameraCase> cameraCases() {
  const glm::dmat4 view = viewFromWorldLookAt({3, 2.5, 5}, {0, 0.5, 0}, {0, 1, 0});
  const glm::dmat4 farView = viewFromWorldLookAt({200, 140, 130}, {0, 5, 0}, {0, 1, 0});
  glm::dmat4 mirror(1.0);
  mirror[0][0] = -1.0;  // x flipped in view space: a mirrored image (det < 0)
  std::vector<CameraCase> cases;
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    cases.push_back(
        {"perspective", perspectiveClipFromView(1.0, 1.5, 0.1, 100.0, mode) * view, mode});
    cases.push_back(
        {"infinite", perspectiveClipFromView(1.0, 1.5, 0.1, std::nullopt, mode) * view, mode});
    cases.push_back(
        {"far_from_origin", perspectiveClipFromView(0.7, 1.5, 0.01, 1000.0, mode) * farView, mode});
    cases.push_back(
        {"orthographic", orthographicClipFromView(-3, 5, -2, 4, 1.0, 50.0, mode) * view, mode});
    cases.push_back(
        {"mirrored", perspectiveClipFromView(1.0, 1.5, 0.1, 100.0, mode) * mirror * view, mode});
  }
  return cases;
}

TEST(RobustRays, OriginOnTheNearPlaneAndRayThroughThePixel) {
  for (const CameraCase& c : cameraCases()) {
    const RobustRayGenerator generator(c.clipFromWorld, c.mode);
    const double bound = 16.0 * conditionNumber(c.clipFromWorld) * kEps;
    for (double x : {-0.999, -0.3, 0.0, 0.51, 0.999}) {
      for (double y : {-0.999, 0.25, 0.999}) {
        const Ray ray = generator.generate({x, y});
        SCOPED_TRACE(std::string(c.name) + " " + c.mode.name());
        EXPECT_NEAR(glm::length(ray.direction), 1.0, 4 * kEps);
        const glm::dvec3 origin = clipNdc(c.clipFromWorld, ray.origin);
        EXPECT_NEAR(origin.x, x, bound);
        EXPECT_NEAR(origin.y, y, bound);
        EXPECT_NEAR(origin.z, c.mode.nearNdcZ(), bound);
        // A point further along projects to the same pixel, deeper into the frustum.
        const double t = std::isfinite(ray.tMax) ? ray.tMax * 0.5 : 10.0;
        const glm::dvec3 inside = clipNdc(c.clipFromWorld, ray.origin + t * ray.direction);
        EXPECT_NEAR(inside.x, x, bound);
        EXPECT_NEAR(inside.y, y, bound);
        if (c.mode.reversed) {
          EXPECT_LT(inside.z, origin.z);
        } else {
          EXPECT_GT(inside.z, origin.z);
        }
        if (std::isfinite(ray.tMax)) {
          const glm::dvec3 end = clipNdc(c.clipFromWorld, ray.origin + ray.tMax * ray.direction);
          EXPECT_NEAR(end.z, c.mode.farNdcZ(), bound);
        }
      }
    }
  }
}

TEST(RobustRays, InfiniteFarPlaneGivesInfiniteTMax) {
  const glm::dmat4 view = viewFromWorldLookAt({0, 2, 6}, {0, 1.5, 0}, {0, 1, 0});
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    const RobustRayGenerator generator(
        perspectiveClipFromView(0.9, 1.0, 0.1, std::nullopt, mode) * view, mode);
    for (double x : {-0.9, 0.0, 0.9}) {
      const Ray ray = generator.generate({x, -0.4});
      EXPECT_EQ(ray.tMax, std::numeric_limits<double>::infinity()) << mode.name();
      EXPECT_LT(ray.direction.z, 0.0) << mode.name();  // looking down -z
    }
  }
}

TEST(RobustRays, MatrixBuiltForNoUnderZoStartsAtTheEffectiveNearPlane) {
  // Built for NO with near n, far f; drawn under ZO the rasterizer clips at z_ndc = 0, which is
  // the view distance 2fn/(f+n).
  const double n = 1.0, f = 100.0;
  const glm::dmat4 m = perspectiveClipFromView(glm::radians(60.0), 1.0, n, f, kNegativeOneToOne);
  const Ray underNo = RobustRayGenerator(m, kNegativeOneToOne).generate({0.0, 0.0});
  const Ray underZo = RobustRayGenerator(m, kZeroToOne).generate({0.0, 0.0});
  EXPECT_NEAR(-underNo.origin.z, n, 4 * kEps * f);
  EXPECT_NEAR(-underZo.origin.z, 2 * f * n / (f + n), 4 * kEps * f);
  // Both end on the same far plane.
  EXPECT_NEAR(underNo.origin.z - underNo.tMax, -f, 64 * kEps * f);
  EXPECT_NEAR(underZo.origin.z - underZo.tMax, -f, 64 * kEps * f);
}

TEST(RobustRays, OrthographicRaysShareOneDirection) {
  const glm::dmat4 view = viewFromWorldLookAt({5000, 3000, 4000}, {0, 0, 0}, {0, 1, 0});
  const glm::dmat4 m = orthographicClipFromView(-8, 8, -6, 6, 6000, 8000, kZeroToOne) * view;
  const RobustRayGenerator generator(m, kZeroToOne);
  EXPECT_TRUE(generator.isParallel());
  const Ray a = generator.generate({-0.9, -0.9});
  const Ray b = generator.generate({0.9, 0.7});
  EXPECT_NEAR(glm::length(a.direction - b.direction), 0.0, 4 * kEps);
  EXPECT_NEAR(glm::dot(a.direction, glm::normalize(glm::dvec3(-5000, -3000, -4000))), 1.0,
              4 * kEps);
  EXPECT_NEAR(a.tMax, 2000.0, 2000.0 * 16 * conditionNumber(m) * kEps);
}

TEST(RobustRays, MirroredViewStillLooksForward) {
  glm::dmat4 mirror(1.0);
  mirror[0][0] = -1.0;
  const glm::dmat4 projection = perspectiveClipFromView(1.0, 1.0, 0.1, 10.0, kZeroToOne);
  const glm::dmat4 m = projection * mirror;
  ASSERT_LT(glm::determinant(m) * glm::determinant(projection), 0.0);  // handedness flipped
  const Ray ray = RobustRayGenerator(m, kZeroToOne).generate({0.5, 0.0});
  EXPECT_LT(ray.direction.z, 0.0);
  // Mirrored: clip x = +0.5 lies on the -x side of view space.
  EXPECT_LT(ray.direction.x, 0.0);
}

// User clip planes cut each ray to what every plane keeps: the same line of sight, the origin
// moved forward to where it enters the kept side, tMax to where it leaves; a line of sight a plane
// keeps nothing of gets tMax 0. generateRow (four pixels per instruction) gives generate's bits.
TEST(RobustRays, ClipPlanesCutEachRayToTheKeptInterval) {
  const glm::dmat4 view = viewFromWorldLookAt({3, 2.5, 5}, {0, 0.5, 0}, {0, 1, 0});
  const std::vector<glm::dvec4> planes = {{0.0, -1.0, 0.0, 0.8}, {1.0, 0.0, 0.3, 0.5}};
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    SCOPED_TRACE(mode.name());
    const glm::dmat4 m = perspectiveClipFromView(1.0, 1.5, 0.1, 100.0, mode) * view;
    const RobustRayGenerator open(m, mode);
    const RobustRayGenerator clipped(m, mode, planes);
    int cut = 0, emptied = 0;
    for (double x = -0.95; x < 1.0; x += 0.1) {
      for (double y = -0.95; y < 1.0; y += 0.1) {
        const Ray a = open.generate({x, y});
        const Ray b = clipped.generate({x, y});
        EXPECT_EQ(a.direction, b.direction);
        if (b.tMax == 0.0) {
          ++emptied;  // every point of the open ray is outside some plane
          for (const double s : {0.0, 0.25, 0.5, 0.75, 1.0}) {
            const glm::dvec4 p(a.origin + s * a.tMax * a.direction, 1.0);
            EXPECT_TRUE(glm::dot(planes[0], p) < 1e-12 || glm::dot(planes[1], p) < 1e-12);
          }
          continue;
        }
        // The cut ray lies on the open one, within it, and inside every plane.
        const double start = glm::dot(b.origin - a.origin, a.direction);
        EXPECT_GE(start, 0.0);
        EXPECT_LE(start + b.tMax, a.tMax * (1.0 + 1e-12));
        cut += start > 0.0 || b.tMax < a.tMax;
        for (const glm::dvec4& plane : planes) {
          for (const double s : {0.0, 0.5, 1.0}) {
            const glm::dvec3 p = b.origin + s * b.tMax * b.direction;
            EXPECT_GE(glm::dot(plane, glm::dvec4(p, 1.0)), -1e-12 * (1.0 + glm::length(p)));
          }
        }
      }
    }
    EXPECT_GT(cut, 50);
    EXPECT_GT(emptied, 5);
    // The row kernels and the one-pixel generator agree bit for bit.
    const Viewport viewport{37, 5};
    const PixelCentreRays rows(m, mode, viewport, planes);
    std::vector<Ray> row(37);
    for (int j = 0; j < viewport.height; ++j) {
      rows.row(j, 0, viewport.width, row.data());
      for (int i = 0; i < viewport.width; ++i) {
        const Ray single = clipped.generateForPixel(i, j, viewport);
        EXPECT_EQ(row[i].origin, single.origin) << i << ", " << j;
        EXPECT_EQ(row[i].tMax, single.tMax) << i << ", " << j;
      }
    }
  }
}

// Depth clamp: the rays leave the eye (perspective) or start parallelReach behind the near plane
// (parallel), on the same lines of sight, and end at the far plane unless what lies beyond it is
// drawn. The row kernels give the same bits.
TEST(RobustRays, DepthClampRaysReachInFrontOfTheNearPlane) {
  const glm::dvec3 eye(3, 2.5, 5);
  const glm::dmat4 view = viewFromWorldLookAt(eye, {0, 0.5, 0}, {0, 1, 0});
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    SCOPED_TRACE(mode.name());
    const glm::dmat4 perspective = perspectiveClipFromView(1.0, 1.5, 0.5, 40.0, mode) * view;
    const glm::dmat4 parallel = orthographicClipFromView(-2, 2, -1.5, 1.5, 0.5, 40.0, mode) * view;
    for (const bool beyondFar : {false, true}) {
      const RobustRayGenerator open(perspective, mode);
      const RobustRayGenerator clamped(perspective, mode, {}, {true, 0.0, beyondFar});
      const RobustRayGenerator openParallel(parallel, mode);
      const RobustRayGenerator clampedParallel(parallel, mode, {}, {true, 7.0, beyondFar});
      for (double x = -0.95; x < 1.0; x += 0.3) {
        for (double y = -0.95; y < 1.0; y += 0.3) {
          const Ray a = open.generate({x, y});
          const Ray b = clamped.generate({x, y});
          EXPECT_EQ(a.direction, b.direction);
          EXPECT_LT(glm::length(b.origin - eye), 1e-12);
          // The near point lies 0.5 / cos(angle to the view axis) from the eye; the far end as far
          // from the new origin as from the eye.
          const double toNear = glm::length(a.origin - eye);
          EXPECT_NEAR(toNear, 0.5 / -glm::dot(a.direction, glm::dvec3(matrixRow(view, 2))), 1e-12);
          if (beyondFar) {
            EXPECT_EQ(b.tMax, std::numeric_limits<double>::infinity());
          } else {
            EXPECT_NEAR(b.tMax, a.tMax + toNear, 1e-9 * b.tMax);
          }
          const Ray c = openParallel.generate({x, y});
          const Ray d = clampedParallel.generate({x, y});
          EXPECT_EQ(c.direction, d.direction);
          EXPECT_NEAR(glm::length(d.origin + 7.0 * d.direction - c.origin), 0.0, 1e-12);
          if (beyondFar) {
            EXPECT_EQ(d.tMax, std::numeric_limits<double>::infinity());
          } else {
            EXPECT_NEAR(d.tMax, c.tMax + 7.0, 1e-9 * d.tMax);
          }
        }
      }
      const Viewport viewport{37, 5};
      const PixelCentreRays rows(perspective, mode, viewport, {}, {true, 0.0, beyondFar});
      const PixelCentreRays parallelRows(parallel, mode, viewport, {}, {true, 7.0, beyondFar});
      std::vector<Ray> row(37), parallelRow(37);
      for (int j = 0; j < viewport.height; ++j) {
        rows.row(j, 0, viewport.width, row.data());
        parallelRows.row(j, 0, viewport.width, parallelRow.data());
        for (int i = 0; i < viewport.width; ++i) {
          const Ray single = clamped.generateForPixel(i, j, viewport);
          EXPECT_EQ(row[i].origin, single.origin) << i << ", " << j;
          EXPECT_EQ(row[i].direction, single.direction) << i << ", " << j;
          EXPECT_EQ(row[i].tMax, single.tMax) << i << ", " << j;
          const Ray singleParallel = clampedParallel.generateForPixel(i, j, viewport);
          EXPECT_EQ(parallelRow[i].origin, singleParallel.origin) << i << ", " << j;
          EXPECT_EQ(parallelRow[i].tMax, singleParallel.tMax) << i << ", " << j;
        }
      }
    }
  }
}

}  // namespace
}  // namespace clipray

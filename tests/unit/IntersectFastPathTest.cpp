// The fast path (BVH + SIMD packets) against the brute-force reference: same closest triangle,
// same t, bit for bit, on random and adversarial rays; and watertightness of a closed mesh.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/FrameBins.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/Check.hpp"
#include "support/FastPathScenes.hpp"
#include "support/TestScenes.hpp"

namespace clipray {
namespace {

using namespace testing::fast_path;

constexpr double kInf = std::numeric_limits<double>::infinity();

// closestHits (packets of up to 64 rays), closestHit and closestHitLinear agree bit for bit.
void expectIdentical(const SceneIntersector& intersector, const std::vector<Ray>& rays,
                     const char* what) {
  std::vector<Hit> packet(rays.size());
  intersector.closestHits(rays, packet);
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit linear = intersector.closestHitLinear(rays[i]);
    const Hit single = intersector.closestHit(rays[i]);
    hits += linear.hit();
    ASSERT_EQ(packet[i].primitiveId, linear.primitiveId) << what << " ray " << i;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(packet[i].t), std::bit_cast<std::uint64_t>(linear.t))
        << what << " ray " << i;
    ASSERT_EQ(single.primitiveId, linear.primitiveId) << what << " ray " << i;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(single.t), std::bit_cast<std::uint64_t>(linear.t))
        << what << " ray " << i;
  }
  EXPECT_GT(hits, 0) << what;
}

class FastPath : public ::testing::Test {
 protected:
  Scene scene = testScene();
  glm::dvec3 eye{0.3, 6.0, 9.0};
  SceneIntersector intersector{scene, eye};
  const MeshObject& floor() const { return scene.objects[0]; }
};

TEST_F(FastPath, BuildsABvhOnlyWhenItPays) {
  EXPECT_TRUE(intersector.usesBvh());
  Scene small;
  small.objects.push_back(testing::quad("q", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}));
  small.objects.push_back(testing::icosphere("b", {0, 1, 0}, 0.5, 0));
  EXPECT_FALSE(SceneIntersector(small, {0, 0, 0}).usesBvh());
}

TEST_F(FastPath, CoherentPrimaryRaysMatchTheLinearScan) {
  // A camera's rays in 8x8 tiles, as intersectFrame traces them.
  std::vector<Ray> rays;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const glm::dvec3 target(-5.0 + 10.0 * (x + 0.5) / 64, 0.0, -5.0 + 10.0 * (y + 0.5) / 48);
      rays.push_back({eye, glm::normalize(target - eye), (x + y) % 3 == 0 ? 11.0 : kInf});
    }
  }
  expectIdentical(intersector, rays, "primary");
}

TEST_F(FastPath, RandomRaysMatchTheLinearScan) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Ray> rays;
  for (int k = 0; k < 4000; ++k) {
    Ray ray;
    ray.origin = {unit(rng) * 6, 1.0 + 3.0 * std::abs(unit(rng)), unit(rng) * 6};
    ray.direction = glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)));
    ray.tMax = k % 4 == 0 ? 3.0 : kInf;
    rays.push_back(ray);
  }
  expectIdentical(intersector, rays, "random");
}

TEST_F(FastPath, AdversarialRaysMatchTheLinearScan) {
  // Through vertices, along and through shared edges, grazing the floor, tMax exactly at a hit,
  // zero direction components, non-finite rays and rays without a ray (tMax < 0).
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const MeshObject& mesh = floor();
  std::vector<Ray> rays;
  for (int k = 0; k < 3000; ++k) {
    const glm::u32vec3 tri = mesh.triangles[(k * 7919) % mesh.triangles.size()];
    const glm::dvec3 a = mesh.worldPositions[tri.x], b = mesh.worldPositions[tri.y];
    const glm::dvec3 origin = eye + glm::dvec3(unit(rng), unit(rng), unit(rng));
    glm::dvec3 target;
    switch (k % 4) {
      case 0:
        target = a;
        break;  // a vertex
      case 1:
        target = a + (b - a) * (0.5 + 0.5 * unit(rng));
        break;  // a shared edge
      case 2:
        target = 0.5 * (a + b);
        break;  // an edge midpoint
      default:
        target = a + (b - a) * 0.25;
        break;
    }
    rays.push_back({origin, glm::normalize(target - origin), kInf});
    if (k % 3 == 0) {
      // Along the edge itself, from just above the floor: grazing and coplanar cases.
      const glm::dvec3 along = glm::normalize(b - a);
      rays.push_back({a - 3.0 * along + glm::dvec3(0, 1e-9 * (k % 5), 0), along, kInf});
      rays.push_back(
          {a + glm::dvec3(0, 0.01, 0), glm::normalize(b - a + glm::dvec3(0, -1e-3, 0)), kInf});
    }
  }
  // tMax exactly at the hit found, and one ulp below it.
  const std::size_t base = rays.size();
  for (std::size_t i = 0; i < 400; ++i) {
    const Hit hit = intersector.closestHitLinear(rays[i]);
    if (!hit.hit()) continue;
    rays.push_back({rays[i].origin, rays[i].direction, hit.t});
    rays.push_back({rays[i].origin, rays[i].direction, std::nextafter(hit.t, 0.0)});
  }
  EXPECT_GT(rays.size(), base);
  // Axis-aligned directions (zero components) and special rays.
  rays.push_back({{0.1, 5.0, 0.2}, {0, -1, 0}, kInf});
  rays.push_back({{-8.0, 0.0, 0.0}, {1, 0, 0}, kInf});
  rays.push_back({{0.0, 2.0, -8.0}, {0, 0, 1}, kInf});
  rays.push_back({{0.0, std::nan(""), 0.0}, {0, -1, 0}, kInf});
  rays.push_back({{0.0, 5.0, 0.0}, {0, -1, 0}, -1.0});
  rays.push_back({{0.0, 5.0, 0.0}, {0, -1, 0}, 0.0});
  rays.push_back({{1e7, 3.0, 1e7}, glm::normalize(glm::dvec3(-1e7, -3.0, -1e7)), kInf});
  expectIdentical(intersector, rays, "adversarial");
}

TEST_F(FastPath, TinyDirectionComponentsMatchTheLinearScan) {
  // Packets whose inverse directions are huge or infinite on one axis (subnormal and tiny
  // components of either sign, next to ordinary rays): the packet's interval bounds must still
  // cull conservatively.
  const double tiny[] = {4.9e-324, -4.9e-324, 1e-310, -1e-310, 1e-300, -1e-300, 1e-200, 0x1p-1022};
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Ray> rays;
  for (int packet = 0; packet < 48; ++packet) {
    const int axis = packet % 3;
    for (int k = 0; k < 64; ++k) {
      glm::dvec3 target(unit(rng) * 5.0, 0.0, unit(rng) * 5.0);
      glm::dvec3 direction = glm::normalize(target - eye);
      if ((k + packet) % 3 != 0) direction[axis] = tiny[(k + packet) % 8];
      rays.push_back({eye, direction, packet % 4 == 0 ? 9.0 : kInf});
    }
  }
  expectIdentical(intersector, rays, "tiny components");
}

TEST_F(FastPath, CoplanarTiesGoToTheSmallerIdInPackets) {
  std::vector<Ray> rays;
  for (int k = 0; k < 64; ++k) {
    const glm::dvec3 origin(-0.9 + 0.025 * k, 4.0, -0.5 + 0.01 * k);
    rays.push_back({origin, glm::normalize(glm::dvec3(0.01, -1, 0.02)), kInf});
  }
  std::vector<Hit> hits(rays.size());
  intersector.closestHits(rays, hits);
  const PrimitiveIdTable ids(scene);
  for (const Hit& hit : hits) {
    ASSERT_TRUE(hit.hit());
    EXPECT_EQ(ids.decode(hit.primitiveId).object, 2);  // "decal", not its duplicate "decal2"
  }
  expectIdentical(intersector, rays, "coplanar");
}

TEST_F(FastPath, IntersectFrameMatchesClosestHitPerPixel) {
  AnalyticFrame frame;
  frame.viewport = {37, 29};  // partial tiles at the right and top
  for (int y = 0; y < 29; ++y) {
    for (int x = 0; x < 37; ++x) {
      const glm::dvec3 target(-4.0 + 8.0 * x / 37, 0.0, -4.0 + 8.0 * y / 29);
      Ray ray{eye, glm::normalize(target - eye), kInf};
      if ((x * 31 + y) % 17 == 0) ray.tMax = kNoRayTMax;
      frame.rays.push_back(ray);
    }
  }
  intersectFrame(frame, intersector, 2);
  for (std::size_t i = 0; i < frame.rays.size(); ++i) {
    const Hit expected = intersector.closestHitLinear(frame.rays[i]);
    ASSERT_EQ(frame.hits[i].primitiveId, expected.primitiveId) << i;
    ASSERT_EQ(frame.hits[i].t, expected.t) << i;
  }
}

// The same scene with analytic primitives: the packets trace the triangles, then each ray tests
// the primitives; every path must still give the linear scan's (t, id) bit for bit.
TEST(FastPathPrimitives, PacketsWithAnalyticPrimitivesMatchTheLinearScan) {
  const Scene scene = testSceneWithPrimitives();
  const glm::dvec3 eye{0.3, 6.0, 9.0};
  const SceneIntersector intersector(scene, eye);
  ASSERT_TRUE(intersector.usesBvh());
  const PrimitiveIdTable ids(scene);
  std::vector<Ray> rays;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const glm::dvec3 target(-5.0 + 10.0 * (x + 0.5) / 64, 0.0, -6.0 + 10.0 * (y + 0.5) / 48);
      Ray ray{eye, glm::normalize(target - eye), (x + y) % 3 == 0 ? 11.0 : kInf};
      if ((x + 5 * y) % 29 == 0) ray.tMax = kNoRayTMax;
      rays.push_back(ray);
    }
  }
  // Rays the packets hand to the one-ray path: zero direction components, non-finite.
  rays.push_back({{0.1, 5.0, 0.2}, {0, -1, 0}, kInf});
  rays.push_back({{-2.0, 5.0, 1.0}, {0, -1, 0}, kInf});
  rays.push_back({{2.5, 0.0, 8.0}, {0, 0, -1}, kInf});
  rays.push_back({{0.0, std::nan(""), 0.0}, {0, -1, 0}, kInf});
  expectIdentical(intersector, rays, "primitives");
  int analytic = 0;
  for (const Ray& ray : rays)
    analytic += intersector.isAnalytic(intersector.closestHit(ray).primitiveId);
  EXPECT_GT(analytic, 100);
  // Straight down through the decals and the disk: the first decal wins the three-way tie.
  const Hit tie = intersector.closestHit({{0.25, 4.0, -0.25}, {0, -1, 0}, kInf});
  EXPECT_EQ(tie.t, 2.0);
  EXPECT_EQ(ids.decode(tie.primitiveId).object, 2);
  EXPECT_EQ(
      intersector.intersectOne(ids.firstAnalyticId + 2, {{0.25, 4.0, -0.25}, {0, -1, 0}, kInf}).t,
      2.0);

  // intersectFrame (8 x 8 tiles through closestHitsTile) agrees per pixel.
  AnalyticFrame frame;
  frame.viewport = {37, 29};
  for (int y = 0; y < 29; ++y) {
    for (int x = 0; x < 37; ++x) {
      const glm::dvec3 target(-4.0 + 8.0 * x / 37, 0.0, -5.0 + 8.0 * y / 29);
      frame.rays.push_back({eye, glm::normalize(target - eye), kInf});
    }
  }
  intersectFrame(frame, intersector, 2);
  for (std::size_t i = 0; i < frame.rays.size(); ++i) {
    const Hit expected = intersector.closestHitLinear(frame.rays[i]);
    ASSERT_EQ(frame.hits[i].primitiveId, expected.primitiveId) << i;
    ASSERT_EQ(frame.hits[i].t, expected.t) << i;
  }
}

// ---- Screen-space bins (intersectFrame with a camera) ----

// The camera whose pixel centres lie (dx, dy) pixels from `camera`'s: x_ndc' = x_ndc - shift.
PickingCamera shiftedByPixels(const PickingCamera& camera, double dx, double dy) {
  glm::dmat4 ndcShift(1.0);
  ndcShift[3][0] = -dx * 2.0 / camera.viewport.width;
  ndcShift[3][1] = -dy * 2.0 / camera.viewport.height;
  PickingCamera shifted = camera;
  shifted.clipFromWorld = ndcShift * camera.clipFromWorld;
  return shifted;
}

TEST(FastPathBinned, CameraRaysUseTheBinsAndMatchTheLinearScan) {
  const Scene scene = testSceneWithPrimitives();
  for (const BinnedCase& c : binnedCases()) {
    SCOPED_TRACE(c.name);
    const SceneIntersector intersector = intersectorSeenFrom(scene, c.camera);
    ASSERT_TRUE(intersector.usesBvh());
    AnalyticFrame frame = generateRobustRays(c.camera, 2);
    const std::size_t binned = intersectFrame(frame, intersector, c.camera, 2);
    EXPECT_EQ(binned, tileCount(c.camera.viewport));  // every tile: the robust rays are on-pixel
    EXPECT_FALSE(intersector.bvhBuilt());             // so no tile needed the BVH
    int hits = 0;
    for (const Hit& hit : frame.hits) hits += hit.hit() ? 1 : 0;
    EXPECT_GT(hits, 61 * 47 / 3);
    expectFrameMatchesTheLinearScan(intersector, frame, c.name);
  }
}

TEST(FastPathBinned, RaysComputedPerTileHitWhatTheStoredRaysHit) {
  // robustRayFrame stores no ray: each tile's rays are computed where they are traced. Its hits
  // must be the stored rays' hits bit for bit (61x47: tiles cut short at the right and the top),
  // binned, walking the BVH, and through intersectFrame's fallback for another camera size.
  const Scene scene = testSceneWithPrimitives();
  std::vector<BinnedCase> cases = binnedCases();
  // 133 pixels wide: rays are computed 64 columns at a time, so three groups, the last of five
  // columns (a partial tile).
  for (const BinnedCase& wide : binnedCases({133, 47})) cases.push_back(wide);
  // A NO matrix drawn under reversed-Z ZO (scenes/no_matrix_under_zo.json): its rays start
  // where that convention's near plane lies, and the bins of some tiles, left empty, do not
  // hold what those rays hit. Such tiles must still compute their rays and walk the BVH.
  BinnedCase mismatched = cases[0];
  mismatched.name = "NO matrix under reversed-Z ZO";
  mismatched.camera.mode = kZeroToOneReversed;
  cases.push_back(mismatched);
  for (const BinnedCase& c : cases) {
    SCOPED_TRACE(std::string(c.name) + " at " + std::to_string(c.camera.viewport.width) + "x" +
                 std::to_string(c.camera.viewport.height));
    const int pixels = c.camera.viewport.width * c.camera.viewport.height;
    const SceneIntersector intersector = intersectorSeenFrom(scene, c.camera);
    AnalyticFrame stored = generateRobustRays(c.camera, 2);
    AnalyticFrame computed = robustRayFrame(c.camera);
    EXPECT_TRUE(computed.rays.empty());
    EXPECT_TRUE(computed.hasRays());
    PickingCamera otherSize = c.camera;
    otherSize.viewport.width += 1;
    const auto expectSameHits = [&](const char* path) {
      ASSERT_EQ(computed.hits.size(), stored.hits.size()) << path;
      int hits = 0;
      for (std::size_t i = 0; i < stored.hits.size(); ++i) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(computed.hits[i].t),
                  std::bit_cast<std::uint64_t>(stored.hits[i].t))
            << path << ", pixel " << i;
        ASSERT_EQ(computed.hits[i].primitiveId, stored.hits[i].primitiveId)
            << path << ", pixel " << i;
        hits += stored.hits[i].hit() ? 1 : 0;
      }
      EXPECT_GT(hits, pixels / 3) << path;
    };
    const std::size_t binned = intersectFrame(computed, intersector, c.camera, 2);
    EXPECT_EQ(binned, intersectFrame(stored, intersector, c.camera, 2));
    if (&c == &cases.back()) {
      EXPECT_LT(binned, tileCount(c.camera.viewport));  // some tiles stray from their bins
    } else {
      EXPECT_EQ(binned, tileCount(c.camera.viewport));
    }
    expectSameHits("binned");
    intersectFrame(computed, intersector, 2);
    intersectFrame(stored, intersector, 2);
    expectSameHits("BVH");
    EXPECT_EQ(intersectFrame(computed, intersector, otherSize, 1), 0u);
    expectSameHits("fallback");
  }
}

TEST(FastPathBinned, AFrameWithoutRaysIsRefused) {
  const Scene scene = testSceneWithPrimitives();
  const BinnedCase c = binnedCases()[0];
  const SceneIntersector intersector = intersectorSeenFrom(scene, c.camera);
  AnalyticFrame frame;
  frame.viewport = c.camera.viewport;  // no rays stored, none computed
  EXPECT_THROW(intersectFrame(frame, intersector, c.camera, 1), InternalError);
  EXPECT_THROW(intersectFrame(frame, intersector, 1), InternalError);
  frame.rays.resize(frame.pixelCount() - 1);  // one short
  EXPECT_THROW(intersectFrame(frame, intersector, 1), InternalError);
  // Computed rays for another viewport, or stored and computed rays both: refused too.
  PickingCamera wider = c.camera;
  wider.viewport.width += 8;
  AnalyticFrame otherSize = robustRayFrame(wider);
  otherSize.viewport = c.camera.viewport;
  EXPECT_THROW(intersectFrame(otherSize, intersector, c.camera, 1), InternalError);
  AnalyticFrame both = generateRobustRays(c.camera, 1);
  both.pixelCentreRays = robustRayFrame(c.camera).pixelCentreRays;
  EXPECT_THROW(intersectFrame(both, intersector, c.camera, 1), InternalError);
  both.rays.clear();  // computed only: taken
  EXPECT_EQ(intersectFrame(both, intersector, c.camera, 1), tileCount(c.camera.viewport));
}

TEST(FastPathBinned, RaysOffTheirPixelsWalkTheBvhAndStillMatch) {
  const Scene scene = testSceneWithPrimitives();
  const BinnedCase c = binnedCases()[0];
  const SceneIntersector intersector(scene, {0.3, 6.0, 9.0},  // the eye
                                     SceneIntersector::BvhBuild::WhenFirstNeeded);
  const Viewport v = c.camera.viewport;
  const AnalyticFrame robust = generateRobustRays(c.camera, 1);

  // One ray moved to the next pixel's line of sight: its tile (and only its tile) walks the BVH.
  AnalyticFrame shifted = robust;
  const std::size_t moved = static_cast<std::size_t>(20) * v.width + 13;  // tile (1, 2)
  shifted.rays[moved] = robust.rays[moved + 1];
  EXPECT_FALSE(intersector.bvhBuilt());
  EXPECT_EQ(intersectFrame(shifted, intersector, c.camera, 2), tileCount(v) - 1);
  EXPECT_TRUE(intersector.bvhBuilt());  // built by the tile that walks it
  expectFrameMatchesTheLinearScan(intersector, shifted, "one ray shifted");

  // A y-flipped picking function: no tile can use the bins except where rows coincide.
  AnalyticFrame flipped = robust;
  for (int y = 0; y < v.height; ++y) {
    for (int x = 0; x < v.width; ++x) {
      flipped.rays[static_cast<std::size_t>(y) * v.width + x] =
          robust.rays[static_cast<std::size_t>(v.height - 1 - y) * v.width + x];
    }
  }
  EXPECT_EQ(intersectFrame(flipped, intersector, c.camera, 2), 0u);
  expectFrameMatchesTheLinearScan(intersector, flipped, "y flipped");

  // Rays from the eye (not the near plane), within a quarter pixel otherwise: w = 0 at the
  // origin is below wClip, so they walk the BVH.
  AnalyticFrame fromEye = robust;
  const glm::dvec3 eye{0.3, 6.0, 9.0};
  for (Ray& ray : fromEye.rays) ray.origin = eye;
  EXPECT_EQ(intersectFrame(fromEye, intersector, c.camera, 2), 0u);
  expectFrameMatchesTheLinearScan(intersector, fromEye, "from the eye");
}

// Rays through points a little off the pixel centres (the camera's clip space shifted by a fraction
// of a pixel in x and y): within kRayTolerancePx every tile still uses the bins, whose padding
// is only a little wider, and every hit stays the linear scan's; beyond it every tile walks the
// BVH.
TEST(FastPathBinned, RaysUpToTheToleranceOffTheirCentresStillUseTheBins) {
  const Scene scene = testSceneWithPrimitives();
  for (const BinnedCase& c : binnedCases()) {
    SCOPED_TRACE(c.name);
    const SceneIntersector intersector = intersectorSeenFrom(scene, c.camera);
    const Viewport v = c.camera.viewport;
    for (const double offPx : {0.24, 0.26}) {
      for (const glm::dvec2 sign :
           {glm::dvec2(1, 1), glm::dvec2(1, -1), glm::dvec2(-1, 1), glm::dvec2(-1, -1)}) {
        AnalyticFrame frame =
            generateRobustRays(shiftedByPixels(c.camera, sign.x * offPx, sign.y * offPx), 2);
        const std::size_t binned = intersectFrame(frame, intersector, c.camera, 2);
        EXPECT_EQ(binned, offPx < FrameBins::kRayTolerancePx ? tileCount(v) : 0u)
            << offPx << " px, signs " << sign.x << " " << sign.y;
        expectFrameMatchesTheLinearScan(intersector, frame, std::to_string(offPx) + " px off");
      }
    }
  }
}

// A scene of analytic primitives only goes through the bins' packets too (which check that the
// rays stay on their pixels), and each tile then tests only the primitives whose padded
// projection touches it: the same hits as the linear scan, also for rays 0.24 px off centre.
TEST(FastPathBinned, PrimitivesAreCulledPerTile) {
  Scene scene = testSceneWithPrimitives();
  scene.objects.clear();
  for (const BinnedCase& c : binnedCases()) {
    SCOPED_TRACE(c.name);
    const SceneIntersector intersector = intersectorSeenFrom(scene, c.camera);
    ASSERT_EQ(intersector.triangleCount(), 0u);
    const Viewport v = c.camera.viewport;
    for (const double offPx : {0.0, 0.24}) {
      AnalyticFrame frame = generateRobustRays(shiftedByPixels(c.camera, offPx, -offPx), 2);
      EXPECT_EQ(intersectFrame(frame, intersector, c.camera, 2), tileCount(v)) << offPx;
      expectFrameMatchesTheLinearScan(intersector, frame, std::to_string(offPx) + " px off");
    }
  }
  // Seen from the first camera the sphere covers some tiles but not all; the plane covers all.
  const PickingCamera camera = binnedCases()[0].camera;
  const SceneIntersector intersector(scene, {0.3, 6.0, 9.0});
  const FrameBins bins(intersector, camera.clipFromWorld, camera.mode, camera.viewport, 1);
  ASSERT_TRUE(bins.usable());
  std::size_t sphereTiles = 0, planeTiles = 0;
  for (int ty = 0; ty < (camera.viewport.height + 7) / 8; ++ty) {
    for (int tx = 0; tx < (camera.viewport.width + 7) / 8; ++tx) {
      sphereTiles += bins.primitiveMayCover(0, tx, ty) ? 1 : 0;
      planeTiles += bins.primitiveMayCover(4, tx, ty) ? 1 : 0;
    }
  }
  EXPECT_GT(sphereTiles, 0u);
  EXPECT_LT(sphereTiles, tileCount(camera.viewport) / 2);
  EXPECT_EQ(planeTiles, tileCount(camera.viewport));
}

// A triangle binned by its edges, not only its bounds: the lower-left half of a 64 x 64 frame
// (pixel corners (-0.5, -0.5), (63.5, -0.5), (-0.5, 63.5); inside: x + y <= 63). A half row of
// centres (x, y) .. (x + 3, y) padded by kRayTolerancePx + kMarginPx (0.3125) reaches it exactly
// when x + y <= 63, so 36 of the 64 tiles (tx + ty <= 7) hold it, and of the 16 x 64 half rows the
// sum over x = 0, 4, .., 60 of (64 - x) = 544 -- where its bounds alone would give every tile and
// half row.
TEST(FastPathBinned, BinsFollowTheTriangleEdgesNotJustItsBounds) {
  Scene scene;
  MeshObject half;
  half.name = "half";
  half.worldPositions = {{-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}};
  half.triangles.emplace_back(0, 1, 2);
  scene.objects.push_back(half);
  const Viewport v{64, 64};
  const PickingCamera camera{orthographicClipFromView(-1, 1, -1, 1, 0.5, 10.0, kZeroToOne) *
                                 viewFromWorldLookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0}),
                             kZeroToOne, v};
  const SceneIntersector intersector(scene, {0, 0, 0}, SceneIntersector::BvhBuild::WhenFirstNeeded);
  const FrameBins bins(intersector, camera.clipFromWorld, camera.mode, v, 1);
  ASSERT_TRUE(bins.usable());
  EXPECT_EQ(bins.entryCount(), 36u);
  int halfRows = 0;
  for (int ty = 0; ty < 8; ++ty) {
    for (int tx = 0; tx < 8; ++tx) {
      int entries = 0;
      for (int chunk = 0; chunk < bins.listChunkCount(); ++chunk) {
        for (const BinnedTriangle& entry : bins.list(chunk, tx, ty)) {
          ++entries;
          halfRows += std::popcount(entry.groupMask);
          // Row r, half h of this tile: x = 8 tx + 4 h, y = 8 ty + r.
          for (int bit = 0; bit < 16; ++bit) {
            const int x = 8 * tx + 4 * (bit % 2), y = 8 * ty + bit / 2;
            EXPECT_EQ((entry.groupMask >> bit) & 1, x + y <= 63 ? 1 : 0)
                << "tile " << tx << " " << ty << " bit " << bit;
          }
        }
      }
      EXPECT_EQ(entries, tx + ty <= 7 ? 1 : 0) << "tile " << tx << " " << ty;
    }
  }
  EXPECT_EQ(halfRows, 544);
  // The camera's rays run along -z exactly (two zero direction components) and start 4.5 away
  // from a scene of extent 1: neither keeps them out of the bins' packets.
  AnalyticFrame frame = generateRobustRays(camera, 1);
  ASSERT_EQ(frame.rays[0].direction, glm::dvec3(0, 0, -1));
  EXPECT_EQ(intersectFrame(frame, intersector, camera, 1), tileCount(v));
  EXPECT_FALSE(intersector.bvhBuilt());
  expectFrameMatchesTheLinearScan(intersector, frame, "half");
  int hits = 0;
  for (const Hit& hit : frame.hits) hits += hit.hit() ? 1 : 0;
  // Centres with x + y <= 63: those on the diagonal lie on the edge, which the watertight test
  // counts as inside.
  EXPECT_EQ(hits, 64 * 65 / 2);
}

// Below the BVH threshold the bins still pay (SIMD packets instead of a scan per ray), and need no
// BVH either.
TEST(FastPathBinned, SmallScenesUseTheBinsToo) {
  Scene scene;
  scene.objects.push_back(testing::quad("floor", {-9, 0, -9}, {-9, 0, 9}, {9, 0, 9}, {9, 0, -9}));
  scene.objects.push_back(testing::quad("wall", {-3, 0, -2}, {3, 0, -2}, {3, 4, -2}, {-3, 4, -2}));
  const BinnedCase c = binnedCases()[0];
  const SceneIntersector intersector(scene, {0.3, 6.0, 9.0},
                                     SceneIntersector::BvhBuild::WhenFirstNeeded);
  ASSERT_FALSE(intersector.usesBvh());
  AnalyticFrame frame = generateRobustRays(c.camera, 2);
  EXPECT_EQ(intersectFrame(frame, intersector, c.camera, 2), tileCount(c.camera.viewport));
  EXPECT_FALSE(intersector.bvhBuilt());
  expectFrameMatchesTheLinearScan(intersector, frame, "two quads");
  int wall = 0;
  for (const Hit& hit : frame.hits) wall += hit.primitiveId == 3 || hit.primitiveId == 4 ? 1 : 0;
  EXPECT_GT(wall, 100);
}

// Squares of 100 x 100 at z = depths[k] facing +z, two triangles each, in that order.
MeshObject layersAt(const std::vector<double>& depths) {
  MeshObject layers;
  layers.name = "layers";
  for (const double z : depths) {
    const auto base = static_cast<std::uint32_t>(layers.worldPositions.size());
    layers.worldPositions.insert(layers.worldPositions.end(),
                                 {{-50, -50, z}, {50, -50, z}, {50, 50, z}, {-50, 50, z}});
    layers.triangles.emplace_back(base, base + 1, base + 2);
    layers.triangles.emplace_back(base, base + 2, base + 3);
  }
  return layers;
}

// A 61 x 47 perspective ZO camera at the origin looking along `direction`.
PickingCamera cameraAtTheOrigin(const glm::dvec3& direction) {
  return {perspectiveClipFromView(0.9, 61.0 / 47.0, 0.1, 100.0, kZeroToOne) *
              viewFromWorldLookAt({0, 0, 0}, direction, {0, 1, 0}),
          kZeroToOne,
          {61, 47}};
}

// Ten layers of two triangles, each covering the frame: 10 to 20 entries in every tile, within the
// budget. The tile's depth bound is refreshed every eight entries: at the first refresh every ray
// has hit the layer at z = -4 (listed first), so the bound is w = 4; the nearest layer (z = -2,
// listed fifth: ids 9 and 10) must still be tested, and the layers after it are skipped once the
// bound is refreshed again. The camera looks
// straight down -z, so each layer lies at one clip w (its depth). Every hit is the linear scan's.
TEST(FastPathBinned, LayersBehindTheNearestHitsAreSkippedWithTheSameHits) {
  Scene scene;
  scene.objects.push_back(layersAt({-4.0, -4.5, -5.0, -5.5, -2.0, -2.5, -3.0, -3.5, -6.0, -6.5}));
  const PickingCamera camera = cameraAtTheOrigin({0, 0, -1});
  const SceneIntersector intersector(scene, {0, 0, 0}, SceneIntersector::BvhBuild::WhenFirstNeeded);
  const FrameBins bins(intersector, camera.clipFromWorld, camera.mode, camera.viewport, 1);
  ASSERT_TRUE(bins.usable());
  // Each tile holds one or both triangles of every layer (the diagonals cut some tiles).
  EXPECT_GE(bins.entryCount(), 10 * tileCount(camera.viewport));
  EXPECT_LE(bins.entryCount(), 20 * tileCount(camera.viewport));
  AnalyticFrame frame = generateRobustRays(camera, 1);
  EXPECT_EQ(intersectFrame(frame, intersector, camera, 2), tileCount(camera.viewport));
  expectFrameMatchesTheLinearScan(intersector, frame, "layers");
  for (const Hit& hit : frame.hits) {
    ASSERT_TRUE(hit.primitiveId == 9 || hit.primitiveId == 10) << hit.primitiveId;
  }
}

// 5000 triangles that each cover the whole frame: 48 tiles x 5000 entries is more than the bins
// pay for (16 x (triangles per chunk + tiles)), so the frame walks the BVH -- with the same hits.
TEST(FastPathBinned, TooManyEntriesFallBackToTheBvh) {
  std::vector<double> depths;
  for (int k = 0; k < 2500; ++k) depths.push_back(-2.0 - 0.01 * k);
  Scene scene;
  scene.objects.push_back(layersAt(depths));
  const PickingCamera camera = cameraAtTheOrigin({0.1, 0.2, -1});
  const SceneIntersector intersector(scene, {0, 0, 0}, SceneIntersector::BvhBuild::WhenFirstNeeded);
  const FrameBins bins(intersector, camera.clipFromWorld, camera.mode, camera.viewport, 2);
  EXPECT_FALSE(bins.usable());
  AnalyticFrame frame = generateRobustRays(camera, 2);
  EXPECT_EQ(intersectFrame(frame, intersector, camera, 2), 0u);
  EXPECT_TRUE(intersector.bvhBuilt());
  expectFrameMatchesTheLinearScan(intersector, frame, "stack");
  // The nearest layer wins everywhere (the first two triangles, ids 1 and 2).
  for (const Hit& hit : frame.hits) EXPECT_LE(hit.primitiveId, 2u);
}

TEST(FastPathWatertight, NoPacketRayLeaksThroughAClosedMesh) {
  // Packets of rays from inside a closed icosphere aimed at its vertices and edges: every ray
  // must hit (a miss would be a crack between neighbours).
  Scene scene;
  scene.objects.push_back(testing::icosphere("sphere", {0.3, -0.2, 0.1}, 1.0, 4));
  const SceneIntersector intersector(scene, {0.25, -0.25, 0.0});
  ASSERT_TRUE(intersector.usesBvh());
  const MeshObject& mesh = scene.objects[0];
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Ray> rays;
  for (int k = 0; k < 30000; ++k) {
    // Origins near the centre; a packet's rays share an origin region, like a camera's.
    const glm::dvec3 origin =
        glm::dvec3(0.3, -0.2, 0.1) + 0.05 * glm::dvec3(unit(rng), unit(rng), unit(rng));
    const glm::u32vec3 tri = mesh.triangles[(k / 3) % mesh.triangles.size()];
    const glm::dvec3 a = mesh.worldPositions[tri.x], b = mesh.worldPositions[tri.y];
    const glm::dvec3 target =
        k % 3 == 0 ? a : (k % 3 == 1 ? 0.5 * (a + b) : a + (b - a) * std::abs(unit(rng)));
    rays.push_back({origin, glm::normalize(target - origin), kInf});
  }
  std::vector<Hit> hits(rays.size());
  intersector.closestHits(rays, hits);
  int escaped = 0;
  for (const Hit& hit : hits) escaped += !hit.hit();
  EXPECT_EQ(escaped, 0);
  for (std::size_t i = 0; i < rays.size(); i += 7) {
    const Hit linear = intersector.closestHitLinear(rays[i]);
    ASSERT_EQ(hits[i].primitiveId, linear.primitiveId) << i;
    ASSERT_EQ(hits[i].t, linear.t) << i;
  }
}

}  // namespace
}  // namespace clipray

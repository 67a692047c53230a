#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/intersect/Watertight.hpp"
#include "support/TestScenes.hpp"

namespace clipray {
namespace {

TEST(Watertight, HitsAtTheExpectedDistance) {
  const WatertightRay ray({0.25, 0.25, 5.0}, {0.0, 0.0, -1.0});
  const auto t = intersectTriangle(ray, 100.0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(*t, 5.0);
  EXPECT_FALSE(
      intersectTriangle(ray, 4.0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}).has_value());  // beyond tMax
  EXPECT_FALSE(intersectTriangle(WatertightRay({0.25, 0.25, -5.0}, {0, 0, -1}), 100.0, {0, 0, 0},
                                 {1, 0, 0}, {0, 1, 0})
                   .has_value());  // behind the origin
  EXPECT_FALSE(
      intersectTriangle(ray, 100.0, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}).has_value());  // degenerate
}

TEST(Watertight, SharedDiagonalAndVertexOfAQuadAreHit) {
  // A quad split along its diagonal: rays through points of the shared diagonal must hit at least
  // one of the two triangles, whatever direction they come from. (Shared vertices are covered by
  // the closed-mesh test: a corner of this quad is on its outline, where a miss is legitimate.)
  const glm::dvec3 a(-1, -1, 0), b(1, -1, 0), c(1, 1, 0), d(-1, 1, 0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int misses = 0;
  for (int k = 0; k < 20000; ++k) {
    const double s = unit(rng);
    const glm::dvec3 target(s, s, 0.0);  // on the diagonal a-c
    const glm::dvec3 origin(unit(rng) * 3, unit(rng) * 3, 2.0 + unit(rng));
    const glm::dvec3 direction = glm::normalize(target - origin);
    const WatertightRay ray(origin, direction);
    const bool hit1 = intersectTriangle(ray, 1e9, a, b, c).has_value();
    const bool hit2 = intersectTriangle(ray, 1e9, a, c, d).has_value();
    misses += !(hit1 || hit2);
  }
  EXPECT_EQ(misses, 0);
}

TEST(Watertight, NoRayEscapesAClosedMeshFromInside) {
  Scene scene;
  scene.objects.push_back(testing::icosphere("sphere", {0.3, -0.2, 0.1}, 1.0, 3));
  const SceneIntersector intersector(scene, {0, 0, 0});
  std::mt19937_64 rng(42);
  std::normal_distribution<double> gauss;
  const MeshObject& mesh = scene.objects[0];
  int escaped = 0;
  for (int k = 0; k < 20000; ++k) {
    Ray ray;
    ray.origin = {0.3, -0.2, 0.1};
    // Every third ray aims exactly at a vertex, every third at an edge midpoint: the hard cases.
    if (k % 3 == 0) {
      ray.direction =
          glm::normalize(mesh.worldPositions[k % mesh.worldPositions.size()] - ray.origin);
    } else if (k % 3 == 1) {
      const glm::u32vec3 tri = mesh.triangles[k % mesh.triangles.size()];
      ray.direction = glm::normalize(
          0.5 * (mesh.worldPositions[tri.x] + mesh.worldPositions[tri.y]) - ray.origin);
    } else {
      ray.direction = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    }
    ray.tMax = std::numeric_limits<double>::infinity();
    escaped += !intersector.closestHit(ray).hit();
  }
  EXPECT_EQ(escaped, 0);
}

TEST(SceneIntersector, BvhMatchesTheLinearScanExactly) {
  Scene scene;
  scene.objects.push_back(testing::icosphere("a", {0, 0, 0}, 1.0, 3));
  scene.objects.push_back(testing::icosphere("b", {1.5, 0.2, -0.5}, 0.8, 2));
  scene.objects.push_back(
      testing::quad("floor", {-5, -1, -5}, {-5, -1, 5}, {5, -1, 5}, {5, -1, -5}));
  const SceneIntersector intersector(scene, {0.1, 3.0, 4.0});
  ASSERT_TRUE(intersector.usesBvh());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int k = 0; k < 5000; ++k) {
    Ray ray;
    ray.origin = {unit(rng) * 4, 2.0 + unit(rng), 4.0 + unit(rng)};
    const glm::dvec3 target(unit(rng) * 2, unit(rng), unit(rng));
    ray.direction = glm::normalize(target - ray.origin);
    ray.tMax = (k % 2) ? std::numeric_limits<double>::infinity() : 6.0;
    const Hit fast = intersector.closestHit(ray);
    const Hit linear = intersector.closestHitLinear(ray);
    ASSERT_EQ(fast.primitiveId, linear.primitiveId) << k;
    ASSERT_EQ(fast.t, linear.t) << k;
  }
}

TEST(SceneIntersector, CoplanarTiesGoToTheSmallerId) {
  Scene scene;
  scene.objects.push_back(testing::quad("first", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}));
  scene.objects.push_back(testing::quad("second", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}));
  const SceneIntersector intersector(scene, {0, 0, 0});
  Ray ray{{0.3, 2.0, 0.6}, {0, -1, 0}, 10.0};
  const Hit hit = intersector.closestHit(ray);
  EXPECT_EQ(hit.t, 2.0);
  const PrimitiveIdTable ids(scene);
  EXPECT_EQ(ids.decode(hit.primitiveId).object, 0);
}

}  // namespace
}  // namespace clipray

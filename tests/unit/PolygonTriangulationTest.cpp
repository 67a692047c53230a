// Ear clipping of OBJ polygons: the triangles cover the polygon, no more, no less.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "clipray/scene/MeshFiles.hpp"
#include "clipray/scene/loaders/PolygonTriangulation.hpp"

namespace clipray::meshfiles {
namespace {

double area(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// Every triangle wound as the polygon (normal along +z for these), their areas summing to the
// polygon's, and each triangle's centroid inside the polygon (even-odd rule in xy).
void expectCovers(const std::vector<glm::dvec3>& polygon, double polygonArea) {
  const PolygonTriangles result = triangulatePolygon(polygon);
  ASSERT_EQ(result.triangles.size(), polygon.size() - 2);
  EXPECT_FALSE(result.fanFallback);
  double sum = 0.0;
  for (const auto& t : result.triangles) {
    const glm::dvec3 a = polygon[t[0]], b = polygon[t[1]], c = polygon[t[2]];
    EXPECT_GT(glm::cross(b - a, c - a).z, 0.0);
    sum += area(a, b, c);
    const glm::dvec3 centre = (a + b + c) / 3.0;
    bool inside = false;
    for (std::size_t k = 0, j = polygon.size() - 1; k < polygon.size(); j = k++) {
      const glm::dvec3 p = polygon[k], q = polygon[j];
      if ((p.y > centre.y) != (q.y > centre.y) &&
          centre.x < (q.x - p.x) * (centre.y - p.y) / (q.y - p.y) + p.x) {
        inside = !inside;
      }
    }
    EXPECT_TRUE(inside) << "triangle " << t[0] << " " << t[1] << " " << t[2];
  }
  EXPECT_NEAR(sum, polygonArea, 1e-12 * polygonArea);
}

TEST(PolygonTriangulation, ConvexPolygonsAreTheFanFromTheFirstCorner) {
  const std::vector<glm::dvec3> hexagon = {{2, 0, 0},  {1, 1.7, 0},   {-1, 1.7, 0},
                                           {-2, 0, 0}, {-1, -1.7, 0}, {1, -1.7, 0}};
  const PolygonTriangles result = triangulatePolygon(hexagon);
  ASSERT_EQ(result.triangles.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(result.triangles[k], (std::array<std::size_t, 3>{0, k + 1, k + 2}));
  }
  EXPECT_EQ(result.nonPlanarity, 0.0);
}

TEST(PolygonTriangulation, ConcavePolygonsAreCoveredExactly) {
  // An L (area 3), and a comb whose teeth a fan from corner 0 would bridge (area 8).
  expectCovers({{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}}, 3.0);
  expectCovers({{0, 0, 0},
                {5, 0, 0},
                {5, 2, 0},
                {4, 2, 0},
                {4, 1, 0},
                {3, 1, 0},
                {3, 2, 0},
                {2, 2, 0},
                {2, 1, 0},
                {1, 1, 0},
                {1, 2, 0},
                {0, 2, 0}},
               8.0);  // 5 x 2, less the two 1 x 1 notches
  // The L tilted out of the xy plane keeps its area: the plane is the polygon's own.
  std::vector<glm::dvec3> tilted = {{0, 0, 0}, {2, 0, 0}, {2, 1, 1},
                                    {1, 1, 1}, {1, 2, 2}, {0, 2, 2}};
  const PolygonTriangles result = triangulatePolygon(tilted);
  double sum = 0.0;
  for (const auto& t : result.triangles) sum += area(tilted[t[0]], tilted[t[1]], tilted[t[2]]);
  EXPECT_NEAR(sum, 3.0 * std::sqrt(2.0), 1e-12);
  EXPECT_LT(result.nonPlanarity, 1e-15);
}

TEST(PolygonTriangulation, NonPlanarPolygonsSayHowFarOff) {
  // A unit square with one corner lifted by 0.1: the corners lie 0.025 off the mean plane
  // (alternately above and below it), the diameter is about sqrt(2).
  const PolygonTriangles result =
      triangulatePolygon(std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}});
  EXPECT_EQ(result.triangles.size(), 2u);
  EXPECT_NEAR(
      result.nonPlanarity,
      0.025 * std::cos(std::atan(0.1 / std::sqrt(2.0))) / glm::length(glm::dvec3(1, 1, 0.1)), 1e-3);
}

TEST(PolygonTriangulation, ObjConcaveFacesAndTheNonPlanarWarning) {
  const MeshFileContents l = parseMeshFile(
      "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n", "l.obj");
  ASSERT_EQ(l.objects.size(), 1u);
  double sum = 0.0;
  for (const glm::u32vec3& t : l.objects[0].triangles) {
    const auto& p = l.objects[0].worldPositions;
    sum += area(p[t.x], p[t.y], p[t.z]);
  }
  EXPECT_DOUBLE_EQ(sum, 3.0);  // a fan from corner 1 covered 4
  EXPECT_TRUE(l.warnings.empty());
  const MeshFileContents bent =
      parseMeshFile("v 0 0 0\nv 1 0 0\nv 1 1 0.1\nv 0 1 0\nf 1 2 3 4\n", "bent.obj");
  ASSERT_EQ(bent.warnings.size(), 1u);
  EXPECT_EQ(bent.warnings[0],
            "bent.obj: 1 polygons are not planar (a corner up to 0.018 of the polygon's size off "
            "its mean plane); triangulated in that plane, the triangles are one of several "
            "surfaces they could be");
}

}  // namespace
}  // namespace clipray::meshfiles

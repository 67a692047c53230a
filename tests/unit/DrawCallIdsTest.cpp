// One id per draw call: the raster's mesh per pixel turned into the triangle the comparison needs.

#include <algorithm>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "clipray/SceneBuilder.hpp"
#include "clipray/compare/DrawCallIds.hpp"
#include "clipray/math/Projections.hpp"

namespace clipray {
namespace {

// Mesh 0: the quad |x|, |y| <= 1 at z = 0 (ids 1, 2); mesh 1: |x|, |y| <= 3 at z = -1 (ids 3, 4);
// each split along its (-,-)-(+,+) diagonal. Seen from z = 3 with a 90 degree fov on 8x8 pixels,
// mesh 0 covers NDC |x|, |y| <= 1/3: window [2.67, 5.33] on both axes.
TEST(DrawCallIds, TheTriangleOfTheRastersMesh) {
  const float near[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const float far[] = {-3, -3, -1, 3, -3, -1, 3, 3, -1, -3, 3, -1};
  const std::uint32_t quad[] = {0, 1, 2, 0, 2, 3};
  const TestScene scene =
      SceneBuilder("two quads").mesh("near", near, quad).mesh("far", far, quad).build();
  PickingCamera camera;
  camera.mode = kZeroToOne;
  camera.viewport = {8, 8};
  camera.clipFromWorld = perspectiveClipFromView(glm::radians(90.0), 1.0, 0.1, 100.0, kZeroToOne) *
                         viewFromWorldLookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  AnalyticFrame analytic;
  analytic.viewport = camera.viewport;
  analytic.hits.resize(64);
  for (Hit& hit : analytic.hits) hit = Hit{};
  std::vector<std::uint8_t> meshOfPixel(64, 0);
  const auto at = [](int x, int y) { return static_cast<std::size_t>(y * 8 + x); };

  // (4, 3): the ray hit the near quad's lower-right triangle (id 1), and so did the raster's mesh.
  meshOfPixel[at(4, 3)] = 1;
  analytic.hits[at(4, 3)] = Hit{2.9, 1};
  // (4, 5) reads the far mesh where the ray hit the near one: the far mesh's triangle on the line
  // of sight (NDC (0.125, 0.375)), its upper-left half (x < y): id 4.
  meshOfPixel[at(4, 5)] = 2;
  analytic.hits[at(4, 5)] = Hit{2.9, 2};
  // (3, 0) reads the near mesh below its silhouette, where the line of sight misses it: the
  // triangle whose projection lies nearest, the one with the bottom edge: id 1.
  meshOfPixel[at(3, 0)] = 1;
  analytic.hits[at(3, 0)] = Hit{4.1, 3};
  // (0, 7): background on the raster side stays 0 whatever the ray hit.
  analytic.hits[at(0, 7)] = Hit{4.1, 4};

  const std::vector<std::uint32_t> ids =
      idsFromDrawCalls(scene.model(), camera, meshOfPixel, analytic);
  ASSERT_EQ(ids.size(), 64u);
  EXPECT_EQ(ids[at(4, 3)], 1u);
  EXPECT_EQ(ids[at(4, 5)], 4u);
  EXPECT_EQ(ids[at(3, 0)], 1u);
  EXPECT_EQ(ids[at(0, 7)], 0u);
  EXPECT_EQ(std::count(ids.begin(), ids.end(), 0u), 61);
}

}  // namespace
}  // namespace clipray

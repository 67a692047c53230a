// The captured draws' clip-space triangles (trace/CaptureGeometry.hpp): the reader's lines read
// back, and each triangle's part inside GL's depth clip volume divided into NDC, where it stays
// planar: the plane through its NDC vertices holds the NDC depth of every point of the triangle.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "clipray/math/Projections.hpp"
#include "clipray/trace/CaptureGeometry.hpp"

namespace clipray::trace {
namespace {

// The NDC depth the plane through `t` gives at (x, y).
double planeDepth(const NdcTriangle& t, double x, double y) {
  const glm::dvec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
  return t[0].z - (n.x * (x - t[0].x) + n.y * (y - t[0].y)) / n.z;
}

TEST(CaptureGeometry, ATriangleInsideIsDividedByW) {
  const auto kept = ndcTrianglesInDepth({1, 2, 3, 4}, {-2, 0, 1, 2}, {0, 4, 0.5, 8},
                                        DepthConvention::NegativeOneToOne);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0][0], glm::dvec3(0.25, 0.5, 0.75));
  EXPECT_EQ(kept[0][1], glm::dvec3(-1.0, 0.0, 0.5));
  EXPECT_EQ(kept[0][2], glm::dvec3(0.0, 0.5, 0.0625));
}

TEST(CaptureGeometry, WhatLiesOutsideTheDepthRangeIsCut) {
  // Under ZERO_TO_ONE z < 0 is in front of the near plane; under NEGATIVE_ONE_TO_ONE it is kept
  // down to z = -w.
  const glm::dvec4 a{0, 0, -0.5, 1}, b{1, 0, 0.5, 1}, c{0, 1, 0.5, 1};
  const auto zo = ndcTrianglesInDepth(a, b, c, DepthConvention::ZeroToOne);
  ASSERT_EQ(zo.size(), 2u);  // the triangle less a corner: a quadrilateral, fanned
  for (const NdcTriangle& t : zo) {
    for (const glm::dvec3& v : t) EXPECT_GE(v.z, 0.0);
  }
  EXPECT_EQ(zo[0][0], glm::dvec3(0.5, 0.0, 0.0));  // where a-b crosses z = 0
  EXPECT_EQ(ndcTrianglesInDepth(a, b, c, DepthConvention::NegativeOneToOne).size(), 1u);
  // Entirely beyond the far plane (z > w), or entirely in front of the near one: nothing.
  EXPECT_TRUE(
      ndcTrianglesInDepth({0, 0, 2, 1}, {1, 0, 3, 1}, {0, 1, 2, 1}, DepthConvention::ZeroToOne)
          .empty());
  EXPECT_TRUE(ndcTrianglesInDepth({0, 0, -2, 1}, {1, 0, -3, 1}, {0, 1, -2, 1},
                                  DepthConvention::NegativeOneToOne)
                  .empty());
}

// A world triangle reaching behind the eye, through a perspective camera under both conventions:
// what is kept lies in front of the near plane, and every point of the world triangle in front
// of it projects onto the kept NDC triangles' planes (to 1e-12: double's rounding of the division
// and the plane, on depths of order 1).
TEST(CaptureGeometry, AWorldTriangleThroughTheNearPlaneStaysPlanarInNdc) {
  for (const DepthConvention convention :
       {DepthConvention::NegativeOneToOne, DepthConvention::ZeroToOne}) {
    const DepthMode mode{convention, false, ClipOrigin::LowerLeft};
    const glm::dmat4 m = perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0, mode) *
                         viewFromWorldLookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    const glm::dvec3 wa{-1, -0.5, -3}, wb{2, 0.2, 1}, wc{0.3, 1, -5};  // wb is behind the eye
    const auto kept = ndcTrianglesInDepth(m * glm::dvec4(wa, 1), m * glm::dvec4(wb, 1),
                                          m * glm::dvec4(wc, 1), convention);
    ASSERT_FALSE(kept.empty());
    const double zn = convention == DepthConvention::ZeroToOne ? 0.0 : -1.0;
    for (const NdcTriangle& t : kept) {
      for (const glm::dvec3& v : t) {
        EXPECT_GE(v.z, zn - 1e-15);
        EXPECT_LE(v.z, 1.0);
      }
    }
    int checked = 0;
    for (int i = 0; i <= 20; ++i) {
      for (int j = 0; i + j <= 20; ++j) {
        const double u = i / 20.0, v = j / 20.0;
        const glm::dvec4 p = m * glm::dvec4(wa + u * (wb - wa) + v * (wc - wa), 1.0);
        if (p.z < zn * p.w || p.z > p.w) continue;  // clipped away
        const glm::dvec3 ndc = glm::dvec3(p) / p.w;
        EXPECT_NEAR(planeDepth(kept[0], ndc.x, ndc.y), ndc.z, 1e-12) << u << " " << v;
        ++checked;
      }
    }
    EXPECT_GT(checked, 50);
  }
}

TEST(CaptureGeometry, ReadsTheReadersLines) {
  // One triangle: (1, 2, 3, 4), (5, 6, 7, 8), (9, 10, 11, 12) as little-endian float32, base64.
  const std::string clip = "AACAPwAAAEAAAEBAAACAQAAAoEAAAMBAAADgQAAAAEEAABBBAAAgQQAAMEEAAEBB";
  const CapturedDrawGeometry draw =
      capturedDrawGeometry(nlohmann::json{{"kind", "geometry"},
                                          {"event", 17},
                                          {"depth_target", "ResourceId::28"},
                                          {"instances", 1},
                                          {"triangles", 1},
                                          {"clip", clip}});
  EXPECT_EQ(draw.event, 17u);
  EXPECT_EQ(draw.depthTarget, "ResourceId::28");
  ASSERT_EQ(draw.clip.size(), 3u);
  EXPECT_EQ(draw.clip[2], glm::dvec4(9, 10, 11, 12));
  const CapturedDrawGeometry lines = capturedDrawGeometry(nlohmann::json{
      {"kind", "geometry"}, {"event", 9}, {"skipped", "draws LineList, not triangles"}});
  EXPECT_EQ(lines.skipped, "draws LineList, not triangles");
  EXPECT_TRUE(lines.clip.empty());
  try {
    capturedDrawGeometry(
        nlohmann::json{{"kind", "geometry"}, {"event", 17}, {"triangles", 2}, {"clip", clip}});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(),
                 "event 17: 48 bytes of clip coordinates for 2 triangles (48 bytes each)");
  }
}

}  // namespace
}  // namespace clipray::trace

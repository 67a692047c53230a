#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clipray/Conventions.hpp"
#include "clipray/math/Projections.hpp"

namespace clipray {
namespace {

TEST(Conventions, WindowDepthFromNdc) {
  EXPECT_EQ(windowDepthFromNdc(-1.0, DepthConvention::NegativeOneToOne), 0.0);
  EXPECT_EQ(windowDepthFromNdc(0.0, DepthConvention::NegativeOneToOne), 0.5);
  EXPECT_EQ(windowDepthFromNdc(1.0, DepthConvention::NegativeOneToOne), 1.0);
  EXPECT_EQ(windowDepthFromNdc(0.0, DepthConvention::ZeroToOne), 0.0);
  EXPECT_EQ(windowDepthFromNdc(0.25, DepthConvention::ZeroToOne), 0.25);
  EXPECT_EQ(ndcFromWindowDepth(0.75, DepthConvention::NegativeOneToOne), 0.5);
  EXPECT_EQ(ndcFromWindowDepth(0.75, DepthConvention::ZeroToOne), 0.75);
}

TEST(Conventions, PixelCentresLowerLeftOrigin) {
  const Viewport viewport{4, 2};
  EXPECT_EQ(clipXYOfPixelCentre(0, 0, viewport), glm::dvec2(-0.75, -0.5));
  EXPECT_EQ(clipXYOfPixelCentre(3, 1, viewport), glm::dvec2(0.75, 0.5));
  EXPECT_EQ(clipXYOfPixelCentre(1, 0, viewport), glm::dvec2(-0.25, -0.5));
  // 7x3: centres never land on the clip-space border.
  EXPECT_DOUBLE_EQ(clipXYOfPixelCentre(6, 2, {7, 3}).x, 6.0 / 7.0);
  EXPECT_DOUBLE_EQ(clipXYOfPixelCentre(6, 2, {7, 3}).y, 2.0 / 3.0);
}

TEST(Conventions, DepthModeNamesAndPlanes) {
  EXPECT_EQ(DepthMode::parse("no"), kNegativeOneToOne);
  EXPECT_EQ(DepthMode::parse("zo"), kZeroToOne);
  EXPECT_EQ(DepthMode::parse("zo-reversed"), kZeroToOneReversed);
  EXPECT_EQ(DepthMode::parse("no-reversed"), std::nullopt);
  EXPECT_EQ(DepthMode::parse("ZO"), std::nullopt);
  EXPECT_EQ(kZeroToOneReversed.name(), "zo-reversed");
  EXPECT_EQ(kNegativeOneToOne.nearNdcZ(), -1.0);
  EXPECT_EQ(kNegativeOneToOne.farNdcZ(), 1.0);
  EXPECT_EQ(kZeroToOne.nearNdcZ(), 0.0);
  EXPECT_EQ(kZeroToOne.farNdcZ(), 1.0);
  EXPECT_EQ(kZeroToOneReversed.nearNdcZ(), 1.0);
  EXPECT_EQ(kZeroToOneReversed.farNdcZ(), 0.0);
}

TEST(Conventions, DepthQuantum) {
  EXPECT_EQ(depthQuantum(DepthFormat::Unorm16, 0.3), std::ldexp(1.0, -16));
  EXPECT_EQ(depthQuantum(DepthFormat::Unorm24, 0.3), std::ldexp(1.0, -24));
  EXPECT_EQ(depthQuantum(DepthFormat::Float32, 0.75), std::ldexp(1.0, -24));  // ulp in [0.5, 1)
  EXPECT_EQ(depthQuantum(DepthFormat::Float32, 1e-3),
            std::ldexp(1.0, -33));  // ulp in [2^-10, 2^-9)
  EXPECT_EQ(parseDepthFormat("32f"), DepthFormat::Float32);
  EXPECT_EQ(parseDepthFormat("32"), std::nullopt);
  EXPECT_EQ(parseVertexMode("camera-relative"), VertexMode::CameraRelative);
}

// z_ndc of a view-space point at distance `distance` in front of the camera.
double ndcDepthAt(const glm::dmat4& clipFromView, double distance) {
  const glm::dvec4 c = clipFromView * glm::dvec4(0.0, 0.0, -distance, 1.0);
  return c.z / c.w;
}

TEST(Projections, PerspectiveMapsNearAndFarToEachConvention) {
  const double n = 0.1, f = 100.0;
  // A few roundings of O(f/(f-n)) terms: 8 ulps of 1 is a generous bound.
  const double bound = 8 * std::numeric_limits<double>::epsilon();
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    const glm::dmat4 p = perspectiveClipFromView(glm::radians(60.0), 1.5, n, f, mode);
    EXPECT_NEAR(ndcDepthAt(p, n), mode.nearNdcZ(), bound) << mode.name();
    EXPECT_NEAR(ndcDepthAt(p, f), mode.farNdcZ(), bound) << mode.name();
  }
}

TEST(Projections, InfinitePerspectiveApproachesTheFarValue) {
  const double n = 0.5;
  EXPECT_EQ(ndcDepthAt(perspectiveClipFromView(1.0, 1.0, n, std::nullopt, kNegativeOneToOne), 4.0),
            1.0 - 2 * n / 4.0);
  EXPECT_EQ(ndcDepthAt(perspectiveClipFromView(1.0, 1.0, n, std::nullopt, kZeroToOne), 4.0),
            1.0 - n / 4.0);
  EXPECT_EQ(ndcDepthAt(perspectiveClipFromView(1.0, 1.0, n, std::nullopt, kZeroToOneReversed), 4.0),
            n / 4.0);
  EXPECT_EQ(ndcDepthAt(perspectiveClipFromView(1.0, 1.0, n, std::nullopt, kZeroToOneReversed), n),
            1.0);
}

TEST(Projections, OrthographicMapsNearAndFar) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    const glm::dmat4 p = orthographicClipFromView(-2, 2, -1, 1, 1.0, 9.0, mode);
    EXPECT_DOUBLE_EQ(ndcDepthAt(p, 1.0), mode.nearNdcZ()) << mode.name();
    EXPECT_DOUBLE_EQ(ndcDepthAt(p, 9.0), mode.farNdcZ()) << mode.name();
  }
}

}  // namespace
}  // namespace clipray

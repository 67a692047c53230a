// The polygon offset interval (compare/PolygonOffset.hpp, GL 4.6 14.6.5): m between
// max(|dz/dx|, |dz/dy|) and the gradient's length, r per depth format, the clamp on the side its
// sign names, and the window-space gradient of a plane from clip-space vertices.

#include <gtest/gtest.h>

#include <cmath>

#include "clipray/compare/PolygonOffset.hpp"

namespace clipray {
namespace {

TEST(PolygonOffsetModel, ResolvableDifferencePerFormat) {
  EXPECT_EQ(resolvableDifferenceRange(DepthFormat::Unorm16, 0.5),
            glm::dvec2(std::ldexp(1.0, -16), std::ldexp(1.0, -15)));
  EXPECT_EQ(resolvableDifferenceRange(DepthFormat::Unorm24, 0.5),
            glm::dvec2(std::ldexp(1.0, -24), std::ldexp(1.0, -23)));
  // 32f: 2^(e - 23), e the exponent of the largest depth: 0.75 = 1.5 * 2^-1, 0.25 = 1 * 2^-2.
  EXPECT_EQ(resolvableDifferenceRange(DepthFormat::Float32, 0.75),
            glm::dvec2(std::ldexp(1.0, -24), std::ldexp(1.0, -24)));
  EXPECT_EQ(resolvableDifferenceRange(DepthFormat::Float32, 0.25),
            glm::dvec2(std::ldexp(1.0, -25), std::ldexp(1.0, -25)));
  EXPECT_EQ(resolvableDifferenceRange(DepthFormat::Float32, 1.0),
            glm::dvec2(std::ldexp(1.0, -23), std::ldexp(1.0, -23)));
}

TEST(PolygonOffsetModel, IntervalSpansTheSlopesAndResolvableDifferences) {
  // Gradient (3e-4, -4e-4): m in [4e-4, 5e-4]; 24-bit r in [2^-24, 2^-23].
  const double r = std::ldexp(1.0, -24);
  const OffsetInterval pushed =
      offsetInterval({-1.0, -2.0, 0.0}, 3e-4, -4e-4, 0.5, DepthFormat::Unorm24, 0.0);
  EXPECT_DOUBLE_EQ(pushed.low, -5e-4 - 4.0 * r);
  EXPECT_DOUBLE_EQ(pushed.high, -4e-4 - 2.0 * r);
  const OffsetInterval away =
      offsetInterval({2.0, 1.0, 0.0}, 3e-4, -4e-4, 0.5, DepthFormat::Unorm24, 0.0);
  EXPECT_DOUBLE_EQ(away.low, 8e-4 + r);
  EXPECT_DOUBLE_EQ(away.high, 1e-3 + 2.0 * r);
  // The slack widens m on both sides.
  const OffsetInterval slack =
      offsetInterval({1.0, 0.0, 0.0}, 3e-4, -4e-4, 0.5, DepthFormat::Unorm24, 0.5);
  EXPECT_DOUBLE_EQ(slack.low, 2e-4);
  EXPECT_DOUBLE_EQ(slack.high, 7.5e-4);
}

TEST(PolygonOffsetModel, TheClampBoundsTheSideItsSignNames) {
  EXPECT_EQ(clampOffset(0.3, 0.1), 0.1);
  EXPECT_EQ(clampOffset(-0.3, 0.1), -0.3);
  EXPECT_EQ(clampOffset(-0.3, -0.1), -0.1);
  EXPECT_EQ(clampOffset(0.3, -0.1), 0.3);
  EXPECT_EQ(clampOffset(0.3, 0.0), 0.3);
  const OffsetInterval clamped =
      offsetInterval({-1.0, 0.0, -4.5e-4}, 3e-4, -4e-4, 0.5, DepthFormat::Float32, 0.0);
  EXPECT_DOUBLE_EQ(clamped.low, -4.5e-4);
  EXPECT_DOUBLE_EQ(clamped.high, -4e-4);
}

TEST(PolygonOffsetModel, FixedPointDepthsAreClampedToTheUnitRange) {
  const OffsetBand fixed = offsetBand({-0.2, -0.1}, 0.15, DepthFormat::Unorm24);
  EXPECT_NEAR(fixed.middle, 0.025, 1e-15);
  EXPECT_NEAR(fixed.halfWidth, 0.025, 1e-15);
  const OffsetBand floating = offsetBand({-0.2, -0.1}, 0.15, DepthFormat::Float32);
  EXPECT_NEAR(floating.middle, 0.0, 1e-15);
  EXPECT_NEAR(floating.halfWidth, 0.05, 1e-15);
}

TEST(PolygonOffsetModel, WindowGradientOfAPlaneFromClipVertices) {
  // The plane z_ndc = 0.5 x_ndc - 0.25 y_ndc + 0.1 through three points at different w (clip =
  // ndc * w), one behind the eye (w < 0): the plane is the same.
  const auto clipOf = [](double x, double y, double w) {
    return glm::dvec4(x * w, y * w, (0.5 * x - 0.25 * y + 0.1) * w, w);
  };
  const glm::dvec2 gradient = windowDepthGradient(clipOf(-0.5, 0.2, 2.0), clipOf(0.7, -0.3, 0.5),
                                                  clipOf(0.1, 0.9, -3.0), {200.0, 100.0}, 0.5);
  // dz_w/dx_w = 0.5 (NDC) * 0.5 (window per NDC depth) * 2 / 200 (NDC per pixel).
  EXPECT_NEAR(gradient.x, 0.5 * 0.5 * 2.0 / 200.0, 1e-12);
  EXPECT_NEAR(gradient.y, -0.25 * 0.5 * 2.0 / 100.0, 1e-12);
  // Edge-on: every vertex on the line x = 0.
  EXPECT_TRUE(std::isnan(
      windowDepthGradient({0, 0, 0, 1}, {0, 1, 0.5, 1}, {0, -1, 0.2, 2}, {200.0, 100.0}, 0.5).x));
}

}  // namespace
}  // namespace clipray

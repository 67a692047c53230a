// The logarithmic depth mapping (compare/LogarithmicDepth.hpp): three.js's formula exactly, its
// inverse and slope, and the tolerance holding the shader's float evaluation of it.

#include <gtest/gtest.h>

#include <cmath>

#include "clipray/compare/LogarithmicDepth.hpp"

namespace clipray {
namespace {

constexpr double kFar = 20000.0;

TEST(LogDepthModel, ThreeJsFormula) {
  // logDepthBufFC = 2.0 / (Math.log(camera.far + 1.0) / Math.LN2); gl_FragDepth =
  // log2(vFragDepth) * logDepthBufFC * 0.5, vFragDepth = 1.0 + gl_Position.w.
  const LogDepthMapping three{1.0, kFar, false};
  const double fc = 2.0 / (std::log(kFar + 1.0) / std::log(2.0));
  for (const double w : {0.1, 1.0, 6.0, 150.0, 3000.0, 15000.0}) {
    EXPECT_NEAR(three.windowDepth(w), std::log2(1.0 + w) * fc * 0.5, 1e-15) << w;
  }
  EXPECT_EQ(three.windowDepth(0.0), 0.0);
  EXPECT_NEAR(three.windowDepth(kFar), 1.0, 1e-15);
  const LogDepthMapping reversed{1.0, kFar, true};
  EXPECT_EQ(reversed.windowDepth(0.0), 1.0);
  EXPECT_NEAR(reversed.windowDepth(kFar), 0.0, 1e-15);
}

TEST(LogDepthModel, InverseAndSlope) {
  for (const LogDepthMapping m :
       {LogDepthMapping{1.0, kFar, false}, LogDepthMapping{1.0, kFar, true},
        LogDepthMapping{0.05, kFar, false}, LogDepthMapping{0.05, kFar, true}}) {
    for (const double w : {0.1, 6.0, 150.0, 3000.0, 15000.0}) {
      EXPECT_NEAR(m.clipWOfWindowDepth(m.windowDepth(w)), w, w * 1e-12);
      const double h = w * 1e-6;
      const double difference = (m.windowDepth(w + h) - m.windowDepth(w - h)) / (2.0 * h);
      EXPECT_NEAR(m.slope(w), difference, std::abs(difference) * 1e-6);
      EXPECT_EQ(m.slope(w) < 0.0, m.reversed());
    }
  }
}

// The shader's arithmetic in float (raster.vert's 1 + C w, log_depth.frag's log2 times the float
// uniform times 0.5, 1 - that reversed) lies within the tolerance without any geometric error
// (wError 0, w_min = w) and without storage: terms 1 to 4 of LogarithmicDepth.hpp hold it, at
// every distance from the near plane to far.
TEST(LogDepthModel, ToleranceHoldsTheShadersFloatArithmetic) {
  int samples = 0;
  for (const LogDepthMapping m :
       {LogDepthMapping{1.0, kFar, false}, LogDepthMapping{1.0, kFar, true},
        LogDepthMapping{0.05, kFar, false}, LogDepthMapping{0.05, kFar, true}}) {
    const float fc = static_cast<float>(2.0 * m.scale());
    for (double w = 0.1; w <= kFar; w *= 1.01) {
      const float wf = static_cast<float>(w);
      const float argument = 1.0f + static_cast<float>(m.constant()) * wf;
      const float l = std::log2(argument) * fc * 0.5f;
      const float stored = m.reversed() ? 1.0f - l : l;
      const double error = std::abs(static_cast<double>(stored) - m.windowDepth(w));
      ASSERT_LE(error, m.tolerance(w, 0.0, w, 0.0)) << "w " << w << " C " << m.constant();
      ++samples;
    }
  }
  EXPECT_EQ(samples, 4 * 1227);  // w from 0.1 up by 1% to far
}

}  // namespace
}  // namespace clipray

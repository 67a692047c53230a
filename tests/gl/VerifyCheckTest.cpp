// `clipray check --verify`: the diagnosis backed by pixels on OSMesa.

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/engine/VerifyCheck.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

using testing::GlTest;

class VerifyCheck : public GlTest {
 protected:
  static CheckInput input(const glm::dmat4& clipFromWorld, DepthConvention declared,
                          bool reversed) {
    CheckInput in;
    in.clipFromWorld = clipFromWorld;
    in.declaredDepth = declared;
    in.declaredReversed = reversed;
    in.depthFormat = DepthFormat::Float32;
    return in;
  }
  static engine::VerifyResult verify(const CheckInput& in) {
    return engine::verifyCheck(in, checkConventions(in), renderer());
  }
};

const glm::dmat4 kView =
    glm::lookAtRH(glm::dvec3(0, 2, 5), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0));

TEST_F(VerifyCheck, NoMatrixUnderZoClipsTheNearProbe) {
  const glm::dmat4 m = glm::perspectiveRH_NO(glm::radians(60.0), 16.0 / 9.0, 0.1, 100.0) * kView;
  const engine::VerifyResult underZo = verify(input(m, DepthConvention::ZeroToOne, false));
  ASSERT_TRUE(underZo.nearProbeDrawn.has_value());
  EXPECT_FALSE(*underZo.nearProbeDrawn);  // at 0.15, inside the effective near plane 0.1998
  EXPECT_TRUE(underZo.reconcile.consistent());
  const engine::VerifyResult underNo = verify(input(m, DepthConvention::NegativeOneToOne, false));
  EXPECT_TRUE(*underNo.nearProbeDrawn);
  EXPECT_TRUE(underNo.nearerProbeWins);
  EXPECT_TRUE(underNo.reconcile.consistent());
}

TEST_F(VerifyCheck, ReversedMatrixWithoutTheReversedDepthTestShowsTheFartherSurface) {
  glm::dmat4 reversed(0.0);
  reversed[0][0] = 1.0;
  reversed[1][1] = 1.5;
  reversed[2][3] = -1.0;
  reversed[3][2] = 0.05;  // z_ndc = 0.05 / distance
  const glm::dmat4 m = reversed * kView;
  const engine::VerifyResult wrong = verify(input(m, DepthConvention::ZeroToOne, false));
  EXPECT_FALSE(wrong.nearerProbeWins);
  EXPECT_FALSE(wrong.reconcile.consistent());
  const engine::VerifyResult right = verify(input(m, DepthConvention::ZeroToOne, true));
  EXPECT_TRUE(right.nearerProbeWins);
  EXPECT_TRUE(right.reconcile.consistent());
  EXPECT_TRUE(*right.nearProbeDrawn);
}

}  // namespace
}  // namespace clipray

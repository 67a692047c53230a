// Which convention an orthographic volume was built for (check/BuiltFor.hpp,
// readOrthographicBuild): the NO and ZO readings of one matrix share the far plane f and satisfy
// zo = (no + f) / 2. What an app sets under either convention is a round number (0: a volume
// starting at the camera) or a volume centred on the camera (near = -far), and a near plane of
// any sign is legal; a matrix is decided only when exactly one reading is such a value.
//
//   NO volume        NO reading   ZO reading   explained     read as
//   [-D, D]          -D (-far)    0            both          ambiguous (one volume, two builds)
//   [-1, 1.1] (OSG)  -1 (round)   0.05 (round) both          ambiguous
//   [0, f]           0            f/2          NO (f/2 not)  no
//   [-3D, D]         -3D          -D (-far)    ZO            zo (a ZO volume centred on the camera)
//   [-0.37, 12.3]    -0.37        5.965        NO            no (a negative near is no evidence)

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/InputError.hpp"
#include "clipray/check/CheckFields.hpp"
#include "clipray/check/ConventionCheck.hpp"

namespace clipray {
namespace {

constexpr auto NO = DepthConvention::NegativeOneToOne;
constexpr auto ZO = DepthConvention::ZeroToOne;

std::vector<std::string> codes(const CheckReport& report) {
  std::vector<std::string> result;
  for (const Finding& f : report.findings) result.push_back(f.severity + ":" + f.code);
  return result;
}

// glOrtho's matrix in float32, as a driver stores it and a trace shows it: a projection alone,
// whose camera is the origin of its own space.
CheckInput glOrtho(double l, double r, double b, double t, double n, double f,
                   DepthConvention declared) {
  glm::dmat4 m = glm::orthoRH_NO(l, r, b, t, n, f);
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) m[column][row] = static_cast<float>(m[column][row]);
  }
  CheckInput input;
  input.projection = m;
  input.view = glm::dmat4(1.0);
  input.clipFromWorld = m;
  input.declaredDepth = declared;
  input.predictMethods = false;
  return input;
}

// OpenSCAD's glOrtho(..., -D, +D) with a non-round D: its ZO reading is exactly 0, which is the
// NO volume centred on the camera; neither that 0 nor the negative NO near decides anything.
TEST(CheckOrthographicBuild, CentredVolumeWithANonRoundDepthIsAmbiguous) {
  for (const DepthConvention declared : {NO, ZO}) {
    const CheckReport r =
        checkConventions(glOrtho(-41.7, 41.7, -23.3, 23.3, -123.4567, 123.4567, declared));
    EXPECT_EQ(r.properties.builtFor, "ambiguous");
    EXPECT_EQ(r.properties.builtForReason,
              "under NO the near plane reads -123.457 (-far, a volume centred on the camera), "
              "under ZO 0 (0, a volume starting at the camera): an app sets either, and the "
              "matrix is that one volume under both; --near settles it");
    EXPECT_EQ(codes(r), std::vector<std::string>{"info:depth-convention-ambiguous"});
  }
}

// OpenSceneGraph's HUD camera: glOrtho(0, W, 0, H, -1, 1.1), "clamped" just past the unit cube.
TEST(CheckOrthographicBuild, ClampedHudVolumeIsNotDecidedByTheSignOfItsNear) {
  const CheckReport r = checkConventions(glOrtho(0.0, 1920.0, 0.0, 1080.0, -1.0, 1.1, ZO));
  EXPECT_EQ(r.properties.builtFor, "ambiguous");
  EXPECT_EQ(r.properties.builtForReason,
            "under NO the near plane reads -1 (within its uncertainty of the round number -1), "
            "under ZO 0.05 (within its uncertainty of the round number 0.05): an app sets "
            "either, and the matrix is that one volume under both; --near settles it");
  EXPECT_EQ(codes(r), std::vector<std::string>{"info:depth-convention-ambiguous"});
  EXPECT_FALSE(r.hasErrors());
}

// A volume starting at the camera under NO: its ZO reading, f/2, is no value anyone sets.
TEST(CheckOrthographicBuild, NoVolumeFromTheCameraIsDecidedNo) {
  const CheckReport r = checkConventions(glOrtho(-4.0, 4.0, -3.0, 3.0, 0.0, 37.3, ZO));
  EXPECT_EQ(r.properties.builtFor, "no");
  EXPECT_EQ(r.properties.builtForReason,
            "the NO reading 0 +-5.2e-06 is 0, a volume starting at the camera; the ZO reading "
            "18.65 +-5.2e-06 lies 0.35 from the nearest round number, 19, and is not -far");
  EXPECT_EQ(codes(r), std::vector<std::string>{"error:depth-convention-mismatch"});
}

// A ZO volume centred on the camera, [-D, D] under ZO, reads [-3D, D] under NO.
TEST(CheckOrthographicBuild, ZoVolumeCentredOnTheCameraIsDecidedZo) {
  // glm::orthoRH_ZO(-4, 4, -3, 3, -12.345, 12.345) is glOrtho's NO matrix with near -37.035.
  const CheckReport r = checkConventions(glOrtho(-4.0, 4.0, -3.0, 3.0, -37.035, 12.345, ZO));
  EXPECT_EQ(r.properties.builtFor, "zo");
  EXPECT_EQ(r.properties.builtForReason,
            "the ZO reading -12.345 +-4.9e-06 is -far, a volume centred on the camera; the NO "
            "reading -37.035 +-8.4e-06 lies 0.0349998 from the nearest round number, -37, and is "
            "not -far");
  EXPECT_TRUE(codes(r).empty());
}

// A negative near is read like any other: round (-0.37) against not round (5.965).
TEST(CheckOrthographicBuild, NegativeNearIsDecidedByRoundnessNotSign) {
  const CheckReport r = checkConventions(glOrtho(-4.0, 4.0, -3.0, 3.0, -0.37, 12.3, NO));
  EXPECT_EQ(r.properties.builtFor, "no");
  EXPECT_TRUE(codes(r).empty());
  // The stated plane settles what the readings leave open.
  CheckInput stated = glOrtho(-41.7, 41.7, -23.3, 23.3, -123.4567, 123.4567, ZO);
  stated.statedNear = -123.4567;
  const CheckReport settled = checkConventions(stated);
  EXPECT_EQ(settled.properties.builtFor, "no");
  EXPECT_EQ(settled.properties.builtForReason, "the stated near plane, -123.457");
  EXPECT_EQ(codes(settled), std::vector<std::string>{"error:depth-convention-mismatch"});
}

}  // namespace
}  // namespace clipray

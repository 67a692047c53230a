// `clipray check`, table-driven: matrices built the way real libraries build them, every property
// and every finding asserted.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/InputError.hpp"
#include "clipray/check/ConventionCheck.hpp"
#include "clipray/check/MatrixReading.hpp"
#include "support/EngineCameras.hpp"

namespace clipray {
namespace {

const glm::dmat4 kViewRH =
    glm::lookAtRH(glm::dvec3(0, 2, 5), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0));
const glm::dmat4 kViewLH =
    glm::lookAtLH(glm::dvec3(0, 2, 5), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0));
const double kFov = glm::radians(60.0);

std::vector<std::string> codes(const CheckReport& report) {
  std::vector<std::string> result;
  for (const Finding& f : report.findings) result.push_back(f.severity + ":" + f.code);
  return result;
}

CheckInput combined(const glm::dmat4& clipFromWorld, std::optional<DepthConvention> declared,
                    bool reversed = false) {
  CheckInput input;
  input.clipFromWorld = clipFromWorld;
  input.declaredDepth = declared;
  input.declaredReversed = reversed;
  return input;
}

CheckInput separate(const glm::dmat4& projection, const glm::dmat4& view,
                    std::optional<DepthConvention> declared) {
  CheckInput input = combined(projection * view, declared);
  input.projection = projection;
  input.view = view;
  return input;
}

constexpr auto NO = DepthConvention::NegativeOneToOne;
constexpr auto ZO = DepthConvention::ZeroToOne;
// Properties come from a float-listed matrix in practice; here from double: 1e-9 relative.
constexpr double kRelative = 1e-9;

// The digits a reading is shown with follow its uncertainty, from 6 down to 1, whatever the
// uncertainty is (fuzz_check_file found an infinite one cast to int).
TEST(ShownReading, DigitsFollowTheUncertaintyEvenWhenItIsInfinite) {
  EXPECT_EQ(shownReading({0.0999999, 1.5e-5}), "0.1");
  EXPECT_EQ(shownReading({0.123456789, 0.0}), "0.123457");
  EXPECT_EQ(shownReading({1e-300, 1e300}), "1e-300");
  EXPECT_EQ(shownReading({2.5, std::numeric_limits<double>::infinity()}), "2");
  EXPECT_EQ(shownReading({std::numeric_limits<double>::infinity(), 1.0}), "inf");
  EXPECT_EQ(shownReading({std::nan(""), 1.0}), "nan");
}

TEST(ConventionCheck, GlmPerspectiveRhNoDrawnUnderNo) {
  const CheckReport r =
      checkConventions(combined(glm::perspectiveRH_NO(kFov, 16.0 / 9.0, 0.1, 100.0) * kViewRH, NO));
  const MatrixProperties& p = r.properties;
  EXPECT_TRUE(p.perspective);
  EXPECT_FALSE(p.oblique || p.offAxis || p.leftHanded || p.reversed || p.yFlipped ||
               p.likelyTransposed);
  EXPECT_EQ(p.builtFor, "no");
  EXPECT_NEAR(p.near->value, 0.1, 0.1 * kRelative);
  EXPECT_NEAR(p.far->value, 100.0, 100.0 * kRelative);
  EXPECT_FALSE(p.infiniteFar);
  EXPECT_NEAR(p.fovYDegrees.value, 60.0, 60.0 * kRelative);
  EXPECT_NEAR(p.fovXDegrees.value, 2 * glm::degrees(std::atan(std::tan(kFov / 2) * 16.0 / 9.0)),
              kRelative * 100);
  EXPECT_NEAR(glm::distance(*p.eye, glm::dvec3(0, 2, 5)), 0.0, 1e-12);
  EXPECT_NEAR(glm::distance(p.viewDirection, glm::normalize(glm::dvec3(0, -2, -5))), 0.0, 1e-12);
  EXPECT_TRUE(r.findings.empty());
}

TEST(ConventionCheck, GlmPerspectiveRhNoDrawnUnderZoIsAMismatch) {
  const CheckReport r =
      checkConventions(combined(glm::perspectiveRH_NO(kFov, 16.0 / 9.0, 0.1, 100.0) * kViewRH, ZO));
  EXPECT_EQ(codes(r), std::vector<std::string>{"error:depth-convention-mismatch"});
  // Under ZO the rasterizer clips at z_ndc = 0: distance 2fn/(f+n).
  EXPECT_NEAR(r.properties.near->value, 2 * 100 * 0.1 / 100.1, 1e-12);
  EXPECT_EQ(r.findings[0].message,
            "built for NEGATIVE_ONE_TO_ONE (near 0.1) but drawn under ZERO_TO_ONE: the rasterizer "
            "clips at z_ndc = 0, "
            "so the effective near plane moves to 0.1998 (1.998x) and NDC [-1, 0), half the depth "
            "range, is never "
            "used (read as built for no: the NO reading 0.1 +-1.1e-14 lies within its uncertainty "
            "of the round number 0.1, the ZO reading 0.1998 +-2.3e-14 lies 0.0001998 from the "
            "nearest one, 0.2)");
  EXPECT_TRUE(r.hasErrors());
}

TEST(ConventionCheck, GlmPerspectiveRhZo) {
  const glm::dmat4 m = glm::perspectiveRH_ZO(kFov, 1.5, 0.25, 400.0) * kViewRH;
  const CheckReport underZo = checkConventions(combined(m, ZO));
  EXPECT_EQ(underZo.properties.builtFor, "zo");
  EXPECT_NEAR(underZo.properties.near->value, 0.25, 0.25 * kRelative);
  EXPECT_TRUE(underZo.findings.empty());
  const CheckReport underNo = checkConventions(combined(m, NO));
  EXPECT_EQ(codes(underNo), std::vector<std::string>{"error:depth-convention-mismatch"});
  // Under NO the rasterizer keeps geometry down to z_ndc = -1: fn/(2f - n).
  EXPECT_NEAR(underNo.properties.near->value, 400 * 0.25 / (800 - 0.25), 1e-12);
}

TEST(ConventionCheck, GlmPerspectiveLhZoIsLeftHanded) {
  const CheckReport r =
      checkConventions(combined(glm::perspectiveLH_ZO(kFov, 1.5, 0.5, 50.0) * kViewLH, ZO));
  EXPECT_TRUE(r.properties.leftHanded);
  EXPECT_EQ(r.properties.builtFor, "zo");
  EXPECT_NEAR(r.properties.far->value, 50.0, 50.0 * kRelative);
  EXPECT_EQ(codes(r), std::vector<std::string>{"info:mirrored"});
}

TEST(ConventionCheck, GlmInfinitePerspective) {
  const CheckReport r =
      checkConventions(combined(glm::infinitePerspective(kFov, 1.5, 0.1) * kViewRH, NO));
  const MatrixProperties& p = r.properties;
  EXPECT_TRUE(p.infiniteFar);
  EXPECT_FALSE(p.far.has_value());
  // 1 - 2n/d (NO, near 0.1) and 1 - n/d (ZO, near 0.2) are the same matrix: both round.
  EXPECT_EQ(p.builtFor, "ambiguous");
  EXPECT_NEAR(p.nearIfBuiltForNo->value, 0.1, 1e-12);
  EXPECT_NEAR(p.nearIfBuiltForZo->value, 0.2, 1e-12);
  EXPECT_EQ(codes(r), (std::vector<std::string>{"info:depth-convention-ambiguous",
                                                "warning:infinite-far-plane"}));
}

TEST(ConventionCheck, GlmOrthoVariants) {
  const glm::dmat4 projection = glm::orthoRH_NO(-2.0, 2.0, -1.0, 1.0, 0.5, 50.0);
  const CheckReport r = checkConventions(combined(projection * kViewRH, NO));
  const MatrixProperties& p = r.properties;
  EXPECT_FALSE(p.perspective);
  EXPECT_FALSE(p.eye.has_value());
  EXPECT_NEAR(p.extentX.value, 4.0, 1e-12);
  EXPECT_NEAR(p.extentY.value, 2.0, 1e-12);
  EXPECT_NEAR(*p.depthExtent, 49.5, 1e-12);
  // No view: near and far are offsets from the world origin along the view direction, where the
  // NO reading (-0.5 + 5.385 = 4.885...) and the ZO reading are neither round.
  EXPECT_EQ(p.orthographicAnchor, "world-origin");
  EXPECT_EQ(p.builtFor, "ambiguous");
  EXPECT_EQ(codes(r), std::vector<std::string>{"info:depth-convention-ambiguous"});
  // The projection alone (with an identity view): measured from the camera, near 0.5 reads
  // round under NO.
  const CheckReport alone = checkConventions(separate(projection, glm::dmat4(1.0), NO));
  EXPECT_EQ(alone.properties.builtFor, "no");
  EXPECT_NEAR(alone.properties.near->value, 0.5, 1e-12);
  EXPECT_NEAR(alone.properties.far->value, 50.0, 1e-12);
  // With the view given, near 0.5 reads round under NO (ZO's reading: 25.25).
  const CheckReport withView = checkConventions(separate(projection, kViewRH, NO));
  EXPECT_EQ(withView.properties.builtFor, "no");
  EXPECT_NEAR(withView.properties.near->value, 0.5, 1e-12);
  EXPECT_NEAR(withView.properties.far->value, 50.0, 1e-12);
  // Built for ZO with near 0.5, it reads near -49 under NO: round too, and a negative near is
  // legal in glOrtho, so the matrix alone leaves it open; the stated near plane settles it.
  CheckInput zoUnderNoInput =
      separate(glm::orthoRH_ZO(-2.0, 2.0, -1.0, 1.0, 0.5, 50.0), kViewRH, NO);
  EXPECT_EQ(checkConventions(zoUnderNoInput).properties.builtFor, "ambiguous");
  zoUnderNoInput.statedNear = 0.5;
  const CheckReport zoUnderNo = checkConventions(zoUnderNoInput);
  EXPECT_EQ(zoUnderNo.properties.builtFor, "zo");
  EXPECT_EQ(codes(zoUnderNo), std::vector<std::string>{"error:depth-convention-mismatch"});
}

// gluOrtho2D and glOrtho(..., -1, 1): a view volume centred on the camera. Its NO reading puts
// the near plane behind the camera (-1) and its ZO reading at 0, the same matrix as
// glm::orthoRH_ZO(..., 0, 1): neither is evidence, so no mismatch is claimed either way. The
// orthographic rule (BuiltFor.hpp) in full: tests/unit/CheckOrthographicBuildTest.cpp.
TEST(ConventionCheck, OrthoCentredOnTheCameraIsNotDecidedByTheBehindCameraRule) {
  const glm::dmat4 ui = glm::orthoRH_NO(0.0, 640.0, 0.0, 480.0, -1.0, 1.0);
  for (const DepthConvention declared : {NO, ZO}) {
    const CheckReport r = checkConventions(separate(ui, glm::dmat4(1.0), declared));
    EXPECT_EQ(r.properties.builtFor, "ambiguous");
    EXPECT_EQ(r.properties.builtForReason,
              "under NO the near plane reads -1 (-far, a volume centred on the camera), under ZO "
              "0 (0, a volume starting at the camera): an app sets either, and the matrix is "
              "that one volume under both; --near settles it");
    EXPECT_EQ(codes(r), std::vector<std::string>{"info:depth-convention-ambiguous"});
  }
  const glm::dmat4 cube = glm::orthoRH_NO(-1.0, 1.0, -1.0, 1.0, -1.0, 1.0);
  EXPECT_EQ(checkConventions(separate(cube, glm::dmat4(1.0), NO)).properties.builtFor, "ambiguous");
  // Behind the camera but not centred on it: a negative near is legal in glOrtho, and both
  // readings (-1 and 4) are round, so this is no evidence either.
  const CheckReport offCentre = checkConventions(
      separate(glm::orthoRH_NO(0.0, 640.0, 0.0, 480.0, -1.0, 9.0), glm::dmat4(1.0), ZO));
  EXPECT_EQ(offCentre.properties.builtFor, "ambiguous");
  EXPECT_EQ(offCentre.properties.builtForReason,
            "under NO the near plane reads -1 (within its uncertainty of the round number -1), "
            "under ZO 4 (within its uncertainty of the round number 4): an app sets either, and "
            "the matrix is that one volume under both; --near settles it");
}

// The reversed-Z infinite projection modern engines use: z_ndc = n / distance under ZERO_TO_ONE.
glm::dmat4 reversedInfinite(double fovY, double aspect, double n) {
  glm::dmat4 m(0.0);
  const double focal = 1.0 / std::tan(fovY / 2);
  m[0][0] = focal / aspect;
  m[1][1] = focal;
  m[2][3] = -1.0;
  m[3][2] = n;
  return m;
}

TEST(ConventionCheck, HandMadeReversedInfinite) {
  const glm::dmat4 m = reversedInfinite(kFov, 1.5, 0.05) * kViewRH;
  const CheckReport r = checkConventions(combined(m, ZO, true));
  const MatrixProperties& p = r.properties;
  EXPECT_TRUE(p.reversed);
  EXPECT_TRUE(p.infiniteFar);
  EXPECT_EQ(p.builtFor, "zo-reversed");
  EXPECT_NEAR(p.near->value, 0.05, 1e-12);
  EXPECT_EQ(codes(r), std::vector<std::string>{"warning:infinite-far-plane"});
  // Drawn without the reversed depth test: the farthest surface wins.
  EXPECT_EQ(codes(checkConventions(combined(m, ZO, false))),
            (std::vector<std::string>{"error:reversed-z-mismatch", "warning:infinite-far-plane"}));
  // Reversed under the classic depth mapping gains nothing.
  EXPECT_EQ(codes(checkConventions(combined(m, NO, true))),
            (std::vector<std::string>{"warning:reversed-z-without-zero-to-one",
                                      "warning:infinite-far-plane"}));
}

TEST(ConventionCheck, VulkanStyleYFlip) {
  glm::dmat4 projection = glm::perspectiveRH_ZO(kFov, 1.5, 0.1, 100.0);
  projection[1][1] *= -1.0;
  CheckInput input = separate(projection, kViewRH, ZO);
  input.origin = WindowOrigin::LowerLeft;
  const CheckReport r = checkConventions(input);
  EXPECT_TRUE(r.properties.yFlipped);
  // Flipping y flips the frame; with the flip undone the camera is right-handed, not a mirror.
  EXPECT_FALSE(r.properties.leftHanded);
  EXPECT_EQ(codes(r), (std::vector<std::string>{"warning:y-flipped"}));
  input.origin = WindowOrigin::UpperLeft;
  EXPECT_EQ(codes(checkConventions(input)), (std::vector<std::string>{"info:y-flipped"}));
  // Given as one matrix, the flip shows as a left-handed frame whose screen up points down a
  // Y-up world; GL's default lower-left origin is assumed when none is declared.
  const CheckReport one = checkConventions(combined(projection * kViewRH, ZO));
  EXPECT_TRUE(one.properties.yFlipped);
  EXPECT_FALSE(one.properties.leftHanded);
  EXPECT_EQ(one.properties.builtFor, "zo");
  EXPECT_EQ(codes(one), (std::vector<std::string>{"warning:y-flipped"}));
}

TEST(ConventionCheck, RowByRowListing) {
  const glm::dmat4 m = glm::perspectiveLH_ZO(kFov, 1.5, 0.1, 100.0) * kViewLH;
  // The matrix written row by row (a maths text, a C array m[row][col] of a column-vector
  // matrix): read as column-major, that is the transpose.
  std::vector<double> rowMajor;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) rowMajor.push_back(m[c][r]);
  }
  const CheckReport misread =
      checkConventions(combined(parseMatrix16(rowMajor, false, "--clip-from-world"), ZO));
  EXPECT_TRUE(misread.properties.likelyTransposed);
  EXPECT_EQ(codes(misread), std::vector<std::string>{"error:likely-transposed"});
  const CheckReport read =
      checkConventions(combined(parseMatrix16(rowMajor, true, "--clip-from-world"), ZO));
  EXPECT_FALSE(read.properties.likelyTransposed);
  EXPECT_EQ(codes(read), std::vector<std::string>{"info:mirrored"});
}

TEST(ConventionCheck, ObliqueNearPlane) {
  // Lengyel's oblique near-plane clipping: row 2 replaced so the near plane is a tilted mirror
  // plane.
  glm::dmat4 projection = glm::perspectiveRH_NO(kFov, 1.5, 0.1, 100.0);
  const glm::dvec4 plane(0.0, 0.6, -0.8, -1.0);  // view space, 1 unit in front, tilted
  const glm::dvec4 q(((plane.x > 0) - (plane.x < 0) + projection[2][0]) / projection[0][0],
                     ((plane.y > 0) - (plane.y < 0) + projection[2][1]) / projection[1][1], -1.0,
                     (1.0 + projection[2][2]) / projection[3][2]);
  const glm::dvec4 c = plane * (2.0 / glm::dot(plane, q));
  projection[0][2] = c.x;
  projection[1][2] = c.y;
  projection[2][2] = c.z + 1.0;
  projection[3][2] = c.w;
  const CheckReport r = checkConventions(combined(projection * kViewRH, NO));
  EXPECT_TRUE(r.properties.oblique);
  EXPECT_EQ(codes(r).back(), "info:oblique-near-plane");
}

TEST(ConventionCheck, NearPlaneTooCloseForTheDepthFormat) {
  CheckInput input = combined(glm::perspectiveRH_NO(kFov, 1.5, 0.001, 1000.0) * kViewRH, NO);
  input.depthFormat = DepthFormat::Unorm24;
  input.sceneExtent = std::make_pair(glm::dvec3(-500, -1, -500), glm::dvec3(500, 10, 5));
  const CheckReport r = checkConventions(input);
  ASSERT_EQ(codes(r), std::vector<std::string>{"warning:near-plane-precision"});
  // dz = z^2 (1/n - 1/f) dd = 0.01 z  =>  z = 0.01 / ((1/n - 1/f) 2^-24) = 167.77...
  const double expected = 0.01 / ((1 / 0.001 - 1 / 1000.0) * std::ldexp(1.0, -24));
  EXPECT_NE(r.findings[0].message.find("beyond " + std::to_string(expected).substr(0, 6)),
            std::string::npos)
      << r.findings[0].message << " expected " << expected;
  // Reversed-Z with 32F under ZERO_TO_ONE keeps relative precision: no finding.
  CheckInput reversed = combined(reversedInfinite(kFov, 1.5, 0.001) * kViewRH, ZO, true);
  reversed.depthFormat = DepthFormat::Float32;
  reversed.sceneExtent = input.sceneExtent;
  EXPECT_EQ(codes(checkConventions(reversed)),
            std::vector<std::string>{"warning:infinite-far-plane"});
}

TEST(ConventionCheck, FloatPrecisionRiskFarFromTheOrigin) {
  // Seed 002's renderer case: near 0.01, eye ~280 units from the origin.
  const glm::dmat4 m =
      glm::perspectiveRH_NO(glm::radians(40.0), 16.0 / 9.0, 0.01, 1000.0) *
      glm::lookAtRH(glm::dvec3(200, 140, 130), glm::dvec3(0, 5, 0), glm::dvec3(0, 1, 0));
  const CheckReport r = checkConventions(combined(m, NO));
  EXPECT_EQ(codes(r), std::vector<std::string>{"warning:float-precision-risk"});
  auto method = [&](const std::string& name) {
    for (const MethodPrediction& prediction : r.methods) {
      if (prediction.method == name) return prediction;
    }
    return MethodPrediction{};
  };
  // The known failure (issue 3): two_point in float is above 1 px here; robust stays below the
  // 0.01 px target of every fov >= 1 deg camera.
  EXPECT_GT(method("two_point").angleErrorPx, 1.0);
  EXPECT_LT(method("two_point").angleErrorPxDouble, 0.01);
  EXPECT_LT(method("robust").angleErrorPx, 0.01);
  EXPECT_EQ(method("inverse_pv").unavailable.empty(), false);  // needs separate projection and view
  // The same camera near the origin carries no risk.
  const glm::dmat4 near =
      glm::perspectiveRH_NO(glm::radians(40.0), 16.0 / 9.0, 0.01, 1000.0) *
      glm::lookAtRH(glm::dvec3(2, 1.4, 1.3), glm::dvec3(0, 0.05, 0), glm::dvec3(0, 1, 0));
  EXPECT_TRUE(checkConventions(combined(near, NO)).findings.empty());
}

TEST(ConventionCheck, ReviewedEdgeCases) {
  // A camera 1000 units from the origin with near 0.01 is a projection, not a singular matrix.
  const glm::dmat4 far =
      glm::perspectiveRH_NO(kFov, 1.5, 0.01, 1000.0) *
      glm::lookAtRH(glm::dvec3(1000, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0));
  EXPECT_FALSE(checkConventions(combined(far, NO)).properties.likelyTransposed);
  // An oblique near plane at the origin (no view transform) is not a transposed matrix.
  glm::dmat4 oblique = glm::perspectiveRH_NO(kFov, 1.5, 0.1, 100.0);
  oblique[1][2] = 0.2;  // row 2 gains a y term: the near plane tilts
  const CheckReport obliqueReport = checkConventions(combined(oblique, NO));
  EXPECT_FALSE(obliqueReport.properties.likelyTransposed);
  EXPECT_TRUE(obliqueReport.properties.oblique);
  // glDepthRange(1, 0) with a classic matrix puts near at the larger depth: GL_LESS picks the
  // farthest.
  CheckInput range = combined(glm::perspectiveRH_ZO(kFov, 1.5, 0.1, 100.0) * kViewRH, ZO);
  range.depthRange = {1.0, 0.0};
  EXPECT_EQ(codes(checkConventions(range)), std::vector<std::string>{"error:reversed-z-mismatch"});
  range.declaredReversed = true;
  EXPECT_TRUE(checkConventions(range).findings.empty());
}

// The matrices apps upload, computed in float as they compute them (tests/support/engines/), and
// as an app logs them with %.9g.
namespace engines = testing::engines;

glm::dmat4 fromEngine(const engines::Mat4& m) {
  glm::dmat4 out;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c][r] = m[static_cast<std::size_t>(4 * c + r)];
  return out;
}

glm::dmat4 printed(const glm::dmat4& m) {
  glm::dmat4 out;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      char text[32];
      std::snprintf(text, sizeof text, "%.9g", m[c][r]);
      out[c][r] = std::strtod(text, nullptr);
    }
  }
  return out;
}

const float kFov60 = glm::radians(60.0f);
const engines::Mat4 kFloatViewRH = engines::glmx::lookAtRH<float>({3, 2, 8}, {0, 0, 0}, {0, 1, 0});

TEST(ConventionCheck, Float32RotatedCameraReadsAsBuilt) {
  const glm::dmat4 m = fromEngine(engines::glmx::clipFromWorld<float>(
      engines::glmx::perspectiveRH_NO<float>(kFov60, 16.0f / 9.0f, 0.1f, 100.0f), kFloatViewRH));
  for (const glm::dmat4& listed : {m, printed(m)}) {
    const CheckReport underNo = checkConventions(combined(listed, NO));
    const MatrixProperties& p = underNo.properties;
    EXPECT_EQ(p.precision, "float32");
    EXPECT_FALSE(p.oblique || p.offAxis || p.leftHanded || p.yFlipped || p.reversed);
    EXPECT_EQ(p.builtFor, "no");
    EXPECT_NEAR(p.near->value, 0.1, p.near->error);
    EXPECT_LT(p.near->error, 1e-4);
    EXPECT_NEAR(p.fovYDegrees.value, 60.0, p.fovYDegrees.error + 1e-5);
    EXPECT_TRUE(underNo.findings.empty());
    EXPECT_EQ(codes(checkConventions(combined(listed, ZO))),
              std::vector<std::string>{"error:depth-convention-mismatch"});
  }
}

TEST(ConventionCheck, Float32VulkanFlipAndOffAxisFrustumReadAsBuilt) {
  engines::Mat4 flipped = engines::glmx::perspectiveRH_ZO<float>(kFov60, 1.5f, 0.1f, 100.0f);
  flipped[5] = -flipped[5];  // proj[1][1] *= -1
  const CheckReport vulkan = checkConventions(combined(
      printed(fromEngine(engines::glmx::clipFromWorld<float>(flipped, kFloatViewRH))), ZO));
  EXPECT_EQ(vulkan.properties.builtFor, "zo");
  EXPECT_TRUE(vulkan.properties.yFlipped);
  EXPECT_FALSE(vulkan.properties.leftHanded);
  EXPECT_EQ(codes(vulkan), std::vector<std::string>{"warning:y-flipped"});
  const CheckReport frustum = checkConventions(
      combined(printed(fromEngine(engines::glmx::clipFromWorld<float>(
                   engines::glmx::frustumRH_NO<float>(-0.05f, 0.15f, -0.04f, 0.08f, 0.1f, 100.0f),
                   kFloatViewRH))),
               NO));
  EXPECT_TRUE(frustum.properties.offAxis);
  EXPECT_FALSE(frustum.properties.oblique);
  EXPECT_EQ(frustum.properties.builtFor, "no");
  EXPECT_TRUE(frustum.findings.empty());
}

TEST(ConventionCheck, DirectXMathInMemoryOrderReadsColumnMajor) {
  namespace dx = engines::dxmath;
  const auto view = dx::lookAtLH<float>({3, 2, 8}, {0, 0, 0}, {0, 1, 0});
  const auto projection =
      dx::perspectiveFovLH<float>(dx::convertToRadians(60.0f), 16.0f / 9.0f, 0.1f, 100.0f);
  const engines::Mat4 memory = dx::memoryOrder(dx::multiply(view, projection));
  const CheckReport r = checkConventions(combined(
      parseMatrix16(std::vector<double>(memory.begin(), memory.end()), false, "--clip-from-world"),
      ZO));
  EXPECT_FALSE(r.properties.likelyTransposed);
  EXPECT_EQ(r.properties.builtFor, "zo");
  EXPECT_NEAR(r.properties.fovYDegrees.value, 60.0, 1e-3);         // XMScalarSinCos's approximation
  EXPECT_EQ(codes(r), std::vector<std::string>{"info:mirrored"});  // left-handed, as D3D's world
}

TEST(ConventionCheck, LengyelObliqueWithTheHorizonInViewIsRightHanded) {
  // A reflection camera: the eye mirrored below the water y = 0, looking up 10 degrees (the
  // horizon in view: rays below it never reach the water), a right-handed glm::lookAtRH camera.
  // Lengyel's clip plane is the water, the eye on its negative side, what lies above it kept.
  const glm::dmat4 view =
      glm::lookAtRH(glm::dvec3(0, -2, 0), glm::dvec3(0, -2 + std::tan(glm::radians(10.0)), -1),
                    glm::dvec3(0, 1, 0));
  const glm::dvec4 waterView = glm::transpose(glm::inverse(view)) * glm::dvec4(0, 1, 0, 0);
  engines::Mat4 projection;
  const glm::dmat4 glmProjection = glm::perspectiveRH_NO(kFov, 1.5, 0.1, 100.0);
  for (int i = 0; i < 16; ++i)
    projection[static_cast<std::size_t>(i)] = glmProjection[i / 4][i % 4];
  const auto oblique = engines::oblique::obliqueNearPlane(
      projection, {waterView.x, waterView.y, waterView.z, waterView.w},
      engines::oblique::Depth::NO);
  ASSERT_TRUE(oblique.has_value());
  const CheckReport r = checkConventions(combined(fromEngine(*oblique) * view, NO));
  const MatrixProperties& p = r.properties;
  EXPECT_TRUE(p.oblique);
  EXPECT_FALSE(p.leftHanded);
  EXPECT_FALSE(p.yFlipped);
  EXPECT_NEAR(p.fovYDegrees.value, 60.0, 1e-9);
  EXPECT_EQ(p.builtFor, "ambiguous");  // a tilted near plane's distance is no typed value
  EXPECT_EQ(codes(r), std::vector<std::string>{"info:oblique-near-plane"});
}

TEST(ConventionCheck, NoPixelWithARayLeavesTheMethodsUnmeasured) {
  // A reflection camera looking 30 degrees down with a 45 degree roll, on a 2x2 viewport: only
  // the corner x = y = 1 of the view (39.2 degrees up the diagonal from the centre) looks above
  // the water's horizon; the pixel centres (22.2 degrees) all look below it, so no pixel has a ray.
  // A projection still (a corner of the view has rays), but nothing to measure the methods on.
  const double down = glm::radians(30.0);
  const glm::dvec3 eye(0, -2, 0), forward(0, -std::sin(down), -std::cos(down));
  const glm::dvec3 level(0, std::cos(down), -std::sin(down)), right(1, 0, 0);
  const glm::dvec3 up = std::cos(glm::radians(45.0)) * level - std::sin(glm::radians(45.0)) * right;
  const glm::dmat4 view = glm::lookAtRH(eye, eye + forward, up);
  const glm::dvec4 waterView = glm::transpose(glm::inverse(view)) * glm::dvec4(0, 1, 0, 0);
  engines::Mat4 projection;
  const glm::dmat4 glmProjection = glm::perspectiveRH_NO(kFov, 1.0, 0.1, 100.0);
  for (int i = 0; i < 16; ++i)
    projection[static_cast<std::size_t>(i)] = glmProjection[i / 4][i % 4];
  const auto oblique = engines::oblique::obliqueNearPlane(
      projection, {waterView.x, waterView.y, waterView.z, waterView.w},
      engines::oblique::Depth::NO);
  ASSERT_TRUE(oblique.has_value());
  CheckInput input = combined(fromEngine(*oblique) * view, NO);
  input.viewport = {2, 2};
  const CheckReport r = checkConventions(input);
  ASSERT_FALSE(r.methods.empty());
  int unmeasured = 0;
  for (const MethodPrediction& prediction : r.methods) {
    if (prediction.unavailable.rfind("needs ", 0) == 0) continue;  // inputs a matrix lacks
    EXPECT_EQ(prediction.unavailable, "no sampled pixel has a ray") << prediction.method;
    ++unmeasured;
  }
  EXPECT_EQ(unmeasured, 6);  // the six methods that run from clipFromWorld alone
  EXPECT_NE(checkReportText(r, input).find(
                "float picking rays at this camera: not measured (no sampled pixel has a "
                "ray)\n"),
            std::string::npos)
      << checkReportText(r, input);
  // With a viewport whose corner pixels reach past the horizon, robust measures again.
  input.viewport = {64, 64};
  for (const MethodPrediction& prediction : checkConventions(input).methods) {
    if (prediction.method != "robust") continue;
    EXPECT_TRUE(prediction.unavailable.empty());
    EXPECT_LT(prediction.angleErrorPx, 0.01);
  }
}

TEST(ConventionCheck, BadInput) {
  auto message = [](auto&& call) {
    try {
      call();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([] {
              parseMatrix16({1, 2, 3}, false, "--clip-from-world");
            }),
            "--clip-from-world: expected 16 numbers, got 3");
  std::vector<double> withNan(16, 1.0);
  withNan[5] = std::nan("");
  EXPECT_EQ(message([&] { parseMatrix16(withNan, false, "--projection"); }),
            "--projection: number 6 is nan; expected finite numbers");
  EXPECT_EQ(message([] { checkConventions(combined(glm::dmat4(0.0), NO)); }),
            "--clip-from-world: the matrix is all zero");
  glm::dmat4 singular(1.0);
  singular[1] = singular[0];
  EXPECT_EQ(message([&] { checkConventions(combined(singular, NO)); }).substr(0, 42),
            "--clip-from-world: the matrix is singular ");
  glm::dmat4 noW(1.0);
  noW[3][3] = 0.0;
  EXPECT_EQ(
      message([&] { checkConventions(combined(noW, NO)); }),
      "--clip-from-world: row 3 (w) is all zero: not a projection (every point would have w = 0)");
  glm::dmat4 negativeW(1.0);
  negativeW[3][3] = -1.0;
  EXPECT_EQ(
      message([&] { checkConventions(combined(negativeW, NO)); }),
      "--clip-from-world: row 3 (w) is (0, 0, 0, -1): w <= 0 everywhere, so GL clips every point");
}

}  // namespace
}  // namespace clipray

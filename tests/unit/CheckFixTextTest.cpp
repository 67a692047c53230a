// What `clipray check` tells a user to do, as a new user meets it (issue 42): every fix names what
// applies to this matrix (the glm function of its structure, the layout the user did not give),
// nothing is said of a matrix the check did not read, and no number is printed two ways.

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/check/CheckFields.hpp"
#include "clipray/check/ConventionCheck.hpp"
#include "support/EngineCameras.hpp"

namespace clipray {
namespace {

namespace e = testing::engines;

// The 16 numbers as an app logs them with %.9g, in the order given.
std::string listed(const e::Mat4& m) {
  std::string text;
  for (const double v : m) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g ", v);
    text += buffer;
  }
  return text;
}

CheckReport checkFields(const CheckFields& fields, CheckInput* inputOut = nullptr) {
  CheckInput input = checkInputFrom(fields, "");
  input.predictMethods = false;
  if (inputOut) *inputOut = input;
  return checkConventions(input);
}

const Finding* findingOf(const CheckReport& report, const std::string& code) {
  for (const Finding& f : report.findings)
    if (f.code == code) return &f;
  return nullptr;
}

// A float32 camera: glm's projection times lookAt((3, 2, 8), origin, +y), in float as glm does.
e::Mat4 glmCamera(const e::Mat4& projection, bool leftHanded = false) {
  const e::Vec3T<float> eye{3, 2, 8}, centre{0, 0, 0}, up{0, 1, 0};
  return e::glmx::clipFromWorld<float>(projection, leftHanded
                                                       ? e::glmx::lookAtLH<float>(eye, centre, up)
                                                       : e::glmx::lookAtRH<float>(eye, centre, up));
}

const float kFov = 1.04719755f;  // 60 degrees

// A D3D user's XMMATRIX memory (column-major order of the GL matrix) given as row-major: the fix
// must not suggest the flag already given, and the report must not describe the scrambled matrix.
TEST(CheckFixText, RowMajorGivenForColumnMajorNumbers) {
  const auto projection = e::dxmath::perspectiveFovLH<float>(kFov, 16.0f / 9.0f, 0.1f, 100.0f);
  const auto view = e::dxmath::lookAtLH<float>({3, 2, 8}, {0, 0, 0}, {0, 1, 0});
  CheckFields fields;
  fields.clipFromWorld = listed(e::dxmath::memoryOrder(e::dxmath::multiply(view, projection)));
  fields.layout = "row-major";
  fields.declaredDepth = "zo";
  CheckInput input;
  const CheckReport report = checkFields(fields, &input);
  ASSERT_EQ(report.findings.size(), 1u);
  EXPECT_EQ(report.findings[0].code, "likely-transposed");
  EXPECT_EQ(report.findings[0].message,
            "read row by row (--layout row-major), the numbers do not have a projection's "
            "structure but read column by column they do: they are probably in column-major "
            "order (a GL mat4 or a DirectXMath XMMATRIX as it lies in memory)");
  EXPECT_EQ(report.findings[0].fix,
            "give the numbers with --layout column-major (the default); an app that uploads this "
            "memory with glUniformMatrix4fv(..., GL_FALSE, ...) uploads it correctly");
  EXPECT_EQ(checkReportText(report, input),
            "matrix: no projection as given (its transpose is one); the camera is not read\n"
            "  entries read as float32\n"
            "error [likely-transposed] " +
                report.findings[0].message + "\n  fix: " + report.findings[0].fix +
                "\n1 errors, 0 warnings, 0 notes\n");
  // Given column-major (as they are), the same numbers are a clean LH ZO camera.
  fields.layout = "column-major";
  const CheckReport right = checkFields(fields);
  EXPECT_TRUE(right.findings.size() == 1 && right.findings[0].code == "mirrored");
  EXPECT_EQ(right.properties.builtFor, "zo");
}

TEST(CheckFixText, ColumnMajorGivenForRowByRowNumbersKeepsTheLayoutHint) {
  const e::Mat4 m = glmCamera(e::glmx::perspectiveRH_NO<float>(kFov, 1.5f, 0.1f, 100.0f));
  CheckFields fields;
  fields.clipFromWorld = listed(e::transpose(m));
  fields.declaredDepth = "no";
  const CheckReport report = checkFields(fields);
  ASSERT_EQ(report.findings.size(), 1u);
  EXPECT_EQ(report.findings[0].fix,
            "upload with glUniformMatrix4fv(..., GL_TRUE, ...) or transpose it; if the numbers are "
            "written row by row, clipray check --layout row-major reads them so");
}

struct ConventionFix {
  const char* name;
  e::Mat4 clipFromWorld;
  std::string declared;
  std::string nearPlane;  // --near, where both readings are round
  std::string fix;
  bool separate = false;  // clipFromWorld is the projection, given with glm's lookAtRH view
};
void PrintTo(const ConventionFix& c, std::ostream* os) {
  *os << c.name;
}

class CheckConventionFix : public ::testing::TestWithParam<ConventionFix> {};

// The fix names the glm function with the matrix's structure: orthographic or perspective,
// off-axis (frustum), infinite far, left- or right-handed; and the depth-row edit for any engine.
TEST_P(CheckConventionFix, NamesTheFunctionOfTheMatrixStructure) {
  const ConventionFix& c = GetParam();
  CheckFields fields;
  if (c.separate) {
    // An orthographic near plane is an offset from the camera: give the view that places it.
    fields.projection = listed(c.clipFromWorld);
    fields.view = listed(e::glmx::lookAtRH<float>({3, 2, 8}, {0, 0, 0}, {0, 1, 0}));
  } else {
    fields.clipFromWorld = listed(c.clipFromWorld);
  }
  fields.declaredDepth = c.declared;
  fields.nearPlane = c.nearPlane;
  const CheckReport report = checkFields(fields);
  const Finding* mismatch = findingOf(report, "depth-convention-mismatch");
  ASSERT_NE(mismatch, nullptr) << report.properties.builtFor << ": "
                               << report.properties.builtForReason;
  EXPECT_EQ(mismatch->fix, c.fix);
}

const std::string kToZo =
    "; in any engine, the depth row z replaced by (z + w) / 2) or draw with "
    "glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE)";
const std::string kToNo =
    "; in any engine, the depth row z replaced by 2 z - w) or draw with "
    "glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)";

INSTANTIATE_TEST_SUITE_P(
    Structures, CheckConventionFix,
    ::testing::Values(
        ConventionFix{"perspectiveRH_NO",
                      glmCamera(e::glmx::perspectiveRH_NO<float>(kFov, 1.5f, 0.1f, 100.0f)), "zo",
                      "", "build the projection for ZO (glm::perspectiveRH_ZO" + kToZo},
        ConventionFix{"perspectiveLH_ZO",
                      glmCamera(e::glmx::perspectiveLH_ZO<float>(kFov, 1.5f, 0.1f, 100.0f), true),
                      "no", "", "build the projection for NO (glm::perspectiveLH_NO" + kToNo},
        ConventionFix{
            "frustumRH_NO",
            glmCamera(e::glmx::frustumRH_NO<float>(-0.05f, 0.1f, -0.04f, 0.06f, 0.1f, 100.0f)),
            "zo", "", "build the projection for ZO (glm::frustumRH_ZO" + kToZo},
        ConventionFix{"infinitePerspectiveRH_NO with --near",
                      glmCamera(e::glmx::infinitePerspectiveRH_NO<float>(kFov, 1.5f, 0.1f)), "zo",
                      "0.1", "build the projection for ZO (glm::infinitePerspectiveRH_ZO" + kToZo},
        ConventionFix{"orthoRH_ZO with its view",
                      // Its NO reading, -49, is round too (a negative near is legal in
                      // glOrtho): --near settles it.
                      e::glmx::orthoRH_ZO<float>(-4, 4, -3, 3, 0.5f, 50.0f), "no", "0.5",
                      "build the projection for NO (glm::orthoRH_NO" + kToNo, true}),
    [](const ::testing::TestParamInfo<ConventionFix>& param) {
      std::string name = param.param.name;
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

// Without --declared-depth the report says that the depth state went unchecked (the README's
// NO matrix, which reads as built for NO).
TEST(CheckFixText, WithoutADeclaredDepthTheDepthStateIsSaidToBeUnchecked) {
  CheckFields fields;
  fields.clipFromWorld =
      "0.912245274 -0.138613343 -0.342566192 -0.341881752 0 1.68646216 -0.228377461 "
      "-0.227921158 -0.342092007 -0.369635552 -0.913509846 -0.911684632 2.32286098e-07 0 "
      "8.59233189 8.77496433";
  const CheckReport report = checkFields(fields);
  ASSERT_EQ(report.findings.size(), 1u);
  EXPECT_EQ(report.findings[0].severity, "info");
  EXPECT_EQ(report.findings[0].code, "depth-convention-unchecked");
  EXPECT_EQ(report.findings[0].message,
            "no depth convention declared: the matrix (built for no) was not checked against the "
            "one the app draws under, and the near plane shown is the one GL's default "
            "NEGATIVE_ONE_TO_ONE gives");
  EXPECT_EQ(report.findings[0].fix,
            "give --declared-depth no, zo or zo-reversed (glClipControl's depth mode, and "
            "GL_GREATER with reversed-Z) to check it");
  EXPECT_FALSE(report.hasErrors());
}

// The depth modes' names as reconcile, pick and bench take them, in any case.
TEST(CheckFixText, DeclaredDepthTakesZoReversedAndAnyCase) {
  CheckFields fields;
  fields.clipFromWorld =
      listed(glmCamera(e::glmx::perspectiveRH_ZO<float>(kFov, 1.5f, 0.1f, 100.0f)));
  for (const char* name : {"ZO", "Zo", "zo"}) {
    fields.declaredDepth = name;
    const CheckInput input = checkInputFrom(fields, "");
    EXPECT_EQ(input.declaredDepth, DepthConvention::ZeroToOne) << name;
    EXPECT_FALSE(input.declaredReversed) << name;
  }
  fields.declaredDepth = "zo-reversed";
  const CheckInput reversed = checkInputFrom(fields, "");
  EXPECT_EQ(reversed.declaredDepth, DepthConvention::ZeroToOne);
  EXPECT_TRUE(reversed.declaredReversed);
  fields.declaredDepth = "NO";
  EXPECT_EQ(checkInputFrom(fields, "").declaredDepth, DepthConvention::NegativeOneToOne);
  fields.declaredDepth = "no-reversed";
  try {
    checkInputFrom(fields, "");
    ADD_FAILURE() << "no-reversed accepted";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "--declared-depth: unknown value \"no-reversed\"; expected one of: no, zo, "
                 "zo-reversed");
  }
  fields.declaredDepth = "zo";
  fields.layout = "Row-Major";
  fields.depthBits = "32F";
  fields.origin = "Upper-Left";
  const CheckInput mixed = checkInputFrom(fields, "");
  EXPECT_TRUE(mixed.listedRowMajor);
  EXPECT_EQ(mixed.depthFormat, DepthFormat::Float32);
  EXPECT_EQ(mixed.origin, WindowOrigin::UpperLeft);
}

// A camera built in double and uploaded as float32 (three.js, Filament): the reason names the
// round number the reading lies within its uncertainty of, and the reading as shown, never calls
// 0.099999 itself round.
TEST(CheckFixText, RoundReadingsAreNamedWithTheirUncertainty) {
  const e::Mat4 projection = e::glmx::perspectiveRH_ZO<double>(1.0471975511965976, 1.5, 0.1, 100);
  const e::Mat4 view = e::glmx::lookAtRH<double>({3, 2, 8}, {0, 0, 0}, {0, 1, 0});
  CheckFields fields;
  fields.clipFromWorld = listed(e::roundToFloat32(e::multiply(projection, view)));
  fields.declaredDepth = "no";
  const CheckReport report = checkFields(fields);
  EXPECT_EQ(report.properties.builtFor, "zo");
  const std::string reason =
      "the ZO reading 0.0999994 +-2.6e-06 lies within its uncertainty of the round number 0.1, "
      "the NO reading 0.0500247 +-1.3e-06 lies 2.47279e-05 from the nearest one, 0.05";
  EXPECT_EQ(report.properties.builtForReason, reason);
  ASSERT_NE(findingOf(report, "depth-convention-mismatch"), nullptr);
  EXPECT_EQ(findingOf(report, "depth-convention-mismatch")->message,
            "built for ZERO_TO_ONE (near 0.0999994) but drawn under NEGATIVE_ONE_TO_ONE: the "
            "rasterizer keeps geometry down to z_ndc = -1, at 0.0500247, nearer than the intended "
            "near plane, and spends half the depth range on that sliver (read as built for zo: " +
                reason + ")");
}

// One number, one spelling: the ambiguous note prints the near plane as the report does.
TEST(CheckFixText, TheAmbiguousNotePrintsTheNearPlaneAsTheReportDoes) {
  CheckFields fields;
  fields.clipFromWorld =
      listed(glmCamera(e::glmx::infinitePerspectiveRH_NO<float>(kFov, 1.5f, 0.12294f)));
  fields.declaredDepth = "zo";
  CheckInput input;
  const CheckReport report = checkFields(fields, &input);
  ASSERT_NE(findingOf(report, "depth-convention-ambiguous"), nullptr);
  const std::string both = "(0.12294 if NO, 0.24588 if ZO)";
  EXPECT_EQ(
      findingOf(report, "depth-convention-ambiguous")->message,
      "this matrix reads as built for NO with near 0.12294 or for ZO with near 0.24588 "
      "(neither reading of the near plane is a round number within its uncertainty " +
          both +
          "; --near settles it); under the declared ZERO_TO_ONE the near plane is at 0.24588");
  const std::string text = checkReportText(report, input);
  EXPECT_NE(text.find("  near 0.24588 +-2.6e-06, far infinite,"), std::string::npos) << text;
  EXPECT_NE(text.find("  built for: ambiguous (near 0.12294 if NO, 0.24588 if ZO)\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("0.245879"), std::string::npos) << text;
}

// The infinite-far warning says what the ray table at this camera shows, and the fix takes the
// direction's sign from clip w, as robust does (docs/bench.md).
TEST(CheckFixText, InfiniteFarWarningAgreesWithTheRayTable) {
  // glm's float infinite perspective: listing 4's zero is +0 unless every component of its
  // (backward) d is negative, so its sign is right looking along (-, -, -), wrong along (+, +, +).
  const std::string head =
      "the far plane is at infinity: unproject_glm and two_point unproject the far point, whose w "
      "is 0 (non-finite rays at this camera); seed 002 listing 4 (full) takes the direction's "
      "sign from dot(mw - mz, d), which is exactly 0 here, so from the sign of a zero: ";
  for (const auto& [eye, outcome] :
       {std::pair{300.0f, std::string("right at this camera (see the ray table), but only "
                                      "because of the view direction's octant")},
        std::pair{-300.0f, std::string("backward at this camera")}}) {
    const e::Mat4 projection = e::glmx::infinitePerspectiveRH_NO<float>(0.5235988f, 1.5f, 0.1f);
    const e::Mat4 view = e::glmx::lookAtRH<float>({eye, eye, eye}, {0, 0, 0}, {0, 1, 0});
    CheckFields fields;
    fields.clipFromWorld = listed(e::glmx::clipFromWorld<float>(projection, view));
    fields.declaredDepth = "no";
    fields.viewport = "64x48";
    const CheckInput input = checkInputFrom(fields, "");
    const CheckReport report = checkConventions(input);
    const Finding* warning = findingOf(report, "infinite-far-plane");
    ASSERT_NE(warning, nullptr);
    EXPECT_EQ(warning->message, head + outcome) << checkReportText(report, input);
    EXPECT_EQ(warning->fix,
              "build picking rays from the plane cross product turned to where clip w grows, "
              "dot(mw, d) > 0, in front of the eye at every pixel (clipray's robust method), "
              "starting on the near plane; t_max = +inf");
    for (const MethodPrediction& m : report.methods) {
      if (m.method == "full") {
        EXPECT_EQ(m.backward > 0, eye < 0.0f);
      }
    }
  }
}

// --cull and --front-face: a Vulkan-style y-flipped glm camera keeps the insides with the default
// GL_CCW and is right with GL_CW; the same camera unflipped is right with GL_CCW; --front-face
// without --cull is refused.
TEST(CheckFixText, FaceCullingThroughAYFlippedProjection) {
  e::Mat4 flipped = e::glmx::perspectiveRH_ZO<float>(kFov, 16.0f / 9.0f, 0.1f, 100.0f);
  flipped[5] = -flipped[5];  // Vulkan's y points down: proj[1][1] *= -1
  CheckFields fields;
  fields.clipFromWorld = listed(glmCamera(flipped));
  fields.declaredDepth = "zo";
  fields.cull = "BACK";  // any case, as every name the check takes
  const CheckReport wrong = checkFields(fields);
  const Finding* finding = findingOf(wrong, "face-culling-keeps-insides");
  ASSERT_NE(finding, nullptr);
  EXPECT_EQ(finding->severity, "warning");
  EXPECT_EQ(finding->message.substr(0, 121),
            "face culling (glCullFace(GL_BACK) at --cull, glFrontFace(GL_CCW) at GL's default) "
            "keeps the triangles that wind clockwise");
  EXPECT_EQ(finding->fix.substr(0, 18), "glFrontFace(GL_CW)");
  fields.frontFace = "cw";
  EXPECT_EQ(findingOf(checkFields(fields), "face-culling-keeps-insides"), nullptr);
  fields.clipFromWorld =
      listed(glmCamera(e::glmx::perspectiveRH_ZO<float>(kFov, 16.0f / 9.0f, 0.1f, 100.0f)));
  fields.frontFace = "ccw";
  EXPECT_EQ(findingOf(checkFields(fields), "face-culling-keeps-insides"), nullptr);
  fields.cull.clear();
  try {
    checkFields(fields);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "--front-face needs --cull (back or front): without culling the front face changes "
              "nothing a depth check sees");
  }
}

}  // namespace
}  // namespace clipray

// GL_DEPTH_CLAMP in `clipray check` (check/DepthClampCheck.hpp): --depth-clamp and the check
// file's depthClamp, the note on what it does to picking, and a perspective matrix whose centre
// of projection is at infinity.

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/InputError.hpp"
#include "clipray/check/CheckFields.hpp"
#include "clipray/check/ConventionCheck.hpp"

namespace clipray {
namespace {

// README's camera: glm::perspectiveRH_NO(60 deg, 16/9, 0.1, 100) * lookAtRH((3, 2, 8), 0, +Y)
// in float, logged with %.9g.
const std::string kReadmeMatrix =
    "0.912245274 -0.138613343 -0.342566192 -0.341881752 0 1.68646216 -0.228377461 -0.227921158 "
    "-0.342092007 -0.369635552 -0.913509846 -0.911684632 2.32286098e-07 0 8.59233189 8.77496433";

std::vector<std::string> codes(const CheckReport& report) {
  std::vector<std::string> result;
  for (const Finding& f : report.findings) result.push_back(f.severity + ":" + f.code);
  return result;
}

CheckReport checked(CheckFields fields) {
  CheckInput input = checkInputFrom(fields, "");
  input.predictMethods = false;
  return checkConventions(input);
}

TEST(CheckDepthClamp, PerspectiveNoteSaysWhereAndAtWhatDepth) {
  CheckFields fields;
  fields.clipFromWorld = kReadmeMatrix;
  fields.declaredDepth = "no";
  EXPECT_TRUE(codes(checked(fields)).empty());
  fields.depthClamp = true;
  const CheckReport report = checked(fields);
  ASSERT_EQ(codes(report), std::vector<std::string>{"info:depth-clamp-near-plane"});
  EXPECT_EQ(
      report.findings[0].message,
      "GL_DEPTH_CLAMP is on (--depth-clamp): nothing is clipped at the near plane; a "
      "surface between the eye and the near plane (0.0999999) is drawn at window depth 0, the "
      "near plane's, so a picking ray that starts on the near plane cannot hit it and "
      "unprojecting the depth buffer there gives a point on the near plane, not on the "
      "surface; likewise a surface beyond the far plane (99.999) is drawn at window depth "
      "1, past the end of a ray bounded by it");
  EXPECT_EQ(report.findings[0].fix,
            "while GL_DEPTH_CLAMP is on, start picking rays at the eye (t from 0) and leave them "
            "unbounded beyond the far plane, and read a window depth of exactly 0 or 1 as "
            "clamped, not as a position; or disable it for the passes that are picked");
  // The declared state in the JSON.
  CheckInput input = checkInputFrom(fields, "");
  input.predictMethods = false;
  EXPECT_EQ(checkReportJson(report, input)["declared"]["depth_clamp"], true);
}

TEST(CheckDepthClamp, ReversedDepthRangeAndOrthographicVolume) {
  CheckFields fields;
  fields.clipFromWorld = kReadmeMatrix;
  fields.depthRange = "0.25,0.75";
  fields.depthClamp = true;
  const CheckReport report = checked(fields);
  ASSERT_EQ(codes(report), (std::vector<std::string>{"info:depth-convention-unchecked",
                                                     "info:depth-clamp-near-plane"}));
  EXPECT_NE(report.findings[1].message.find("is drawn at window depth 0.25, the near plane's"),
            std::string::npos)
      << report.findings[1].message;
  EXPECT_NE(report.findings[1].message.find("is drawn at window depth 0.75, past the end"),
            std::string::npos);
  // glOrtho(-2, 2, -1, 1, 1, 9): a parallel volume has no eye; what lies behind the camera is
  // drawn too.
  CheckInput ortho;
  ortho.projection = glm::orthoRH_NO(-2.0, 2.0, -1.0, 1.0, 1.0, 9.0);
  ortho.view = glm::dmat4(1.0);
  ortho.clipFromWorld = *ortho.projection;
  ortho.declaredDepth = DepthConvention::NegativeOneToOne;
  ortho.depthClampEnabledAt = "glEnable(GL_DEPTH_CLAMP) at call 12";
  ortho.predictMethods = false;
  const CheckReport parallel = checkConventions(ortho);
  ASSERT_EQ(codes(parallel), (std::vector<std::string>{"info:depth-convention-ambiguous",
                                                       "info:depth-clamp-near-plane"}));
  EXPECT_EQ(parallel.findings[1].message,
            "GL_DEPTH_CLAMP is on (glEnable(GL_DEPTH_CLAMP) at call 12): nothing is clipped at "
            "the near plane; a surface in front of the near plane (1), however far (a parallel "
            "volume has no eye) is drawn at window depth 0, the near plane's, so a picking ray "
            "that starts on the near plane cannot hit it and unprojecting the depth buffer there "
            "gives a point on the near plane, not on the surface; likewise a surface beyond the "
            "far plane (9) is drawn at window depth 1, past the end of a ray bounded by it");
  EXPECT_EQ(parallel.findings[1].fix,
            "while GL_DEPTH_CLAMP is on, start picking rays at the eye (t from 0, or behind the "
            "near plane for a parallel volume) and leave them unbounded beyond the far plane, "
            "and read a window depth of exactly 0 or 1 as clamped, not as a position; or disable "
            "it for the passes that are picked");
}

TEST(CheckDepthClamp, CheckFileKey) {
  const CheckFields fields = parseCheckFile(
      R"({"clipFromWorld": ")" + kReadmeMatrix + R"(", "depthClamp": true})", "app.json");
  EXPECT_TRUE(fields.depthClamp);
  EXPECT_EQ(*checkInputFrom(fields, "app.json: ").depthClampEnabledAt, "--depth-clamp");
  try {
    parseCheckFile(R"({"clipFromWorld": ")" + kReadmeMatrix + R"(", "depthClamp": "yes"})",
                   "app.json");
    FAIL() << "a string depthClamp was accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "app.json: /depthClamp: unknown key or wrong type (\"yes\"); valid keys: "
              "clipFromWorld, projection, view, layout, declaredDepth, reversed, depthRange, "
              "origin, viewport, depthBits, sceneExtent, precision, near, far, cull, frontFace, "
              "depthClamp, comment");
  }
}

// Rows x, y and w of this matrix span only the x-z directions: they meet at infinity along y,
// as a light-space perspective warp (LiSPSM) can; the report says so instead of "eye (-nan, ...)".
TEST(CheckEyeAtInfinity, SaidInWordsNotAsNaN) {
  glm::dmat4 m(0.0);
  m[0][0] = 1.0;   // x_clip = x
  m[3][1] = 1.0;   // y_clip = 1
  m[1][2] = 1.0;   // z_clip = y
  m[2][3] = -1.0;  // w_clip = -z
  CheckInput input;
  input.clipFromWorld = m;
  input.predictMethods = false;
  const CheckReport report = checkConventions(input);
  ASSERT_TRUE(report.properties.eyeAtInfinityAlong);
  EXPECT_EQ(*report.properties.eyeAtInfinityAlong, glm::dvec3(0.0, 1.0, 0.0));
  const std::string text = checkReportText(report, input);
  EXPECT_NE(text.find("  no eye point: the centre of projection is at infinity along (0, 1, 0) "
                      "(rows x, y and w share no point; a light-space perspective warp such as "
                      "LiSPSM's), looking along (0, 0, -1)\n  near -, far -, fov - (no eye to "
                      "measure it from)\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("nan"), std::string::npos) << text;
  const nlohmann::json json = checkReportJson(report, input);
  EXPECT_TRUE(json["properties"]["eye"].is_null());
  EXPECT_EQ(json["properties"]["eye_at_infinity_along"], nlohmann::json({0.0, 1.0, 0.0}));
  // No eye, no angle: the fov is absent (null), as the text's "fov -", not a zero.
  EXPECT_TRUE(json["properties"]["fov_y_degrees"].is_null());
  EXPECT_TRUE(json["properties"]["fov_x_degrees"].is_null());
  EXPECT_TRUE(json["properties"]["fov_error_degrees"].is_null());
}

}  // namespace
}  // namespace clipray

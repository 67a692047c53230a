// The trace checker (harness/clipray/trace/TraceCheck.*) on dump text: two dumps captured from
// tests/traceapps/ConventionApp.cpp under apitrace 11.1 (tests/data/trace/), and short dumps
// written here for the state the apps do not set.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/trace/TraceCheck.hpp"
#include "clipray/util/Check.hpp"
#include "support/TraceLines.hpp"

namespace clipray::trace {
namespace {

using testing::checkLines;
using testing::codes;

std::string captured(const std::string& name) {
  std::ifstream file(std::string(CLIPRAY_SOURCE_DIR) + "/tests/data/trace/" + name);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string refusal(const std::string& text, FrameRange frames = {}) {
  try {
    checkLines(text, frames);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(accepted)";
}

// glm::perspectiveRH_NO(60 deg, 4/3, 0.1, 100) * lookAtRH((0, 2, 5), 0, +Y) in float, as
// apitrace writes it (7 significant digits).
const std::string kNoMatrix =
    "{1.299038, 0, 0, 0, 0, 1.608169, -0.3721342, -0.3713907, 0, -0.6432676, -0.9303355, "
    "-0.9284767, 0, 0, 5.195746, 5.385165}";

std::string shaderApp(const std::string& setup, const std::string& perFrame, int frames) {
  std::string text =
      "// process.name = \"/tmp/app\"\n1 glViewport(x = 0, y = 0, width = 64, "
      "height = 48) // fake\n2 glEnable(cap = GL_DEPTH_TEST)\n" +
      setup +
      "10 glUseProgram(program = 1)\n"
      "11 glGetUniformLocation(program = 1, name = \"clipFromWorld\") = 0\n";
  int call = 20;
  for (int frame = 0; frame < frames; ++frame) {
    std::istringstream lines(perFrame);
    std::string line;
    while (std::getline(lines, line)) text += std::to_string(call++) + " " + line + "\n";
    text += std::to_string(call++) + " eglSwapBuffers(dpy = 0x1, surface = 0x2) = EGL_TRUE\n";
  }
  return text;
}

TEST(TraceCheck, CapturedNoMatrixUnderZeroToOne) {
  const TraceCheckResult result = checkLines(captured("no-under-zo.dump.txt"));
  EXPECT_EQ(result.framesSeen, 3u);
  EXPECT_EQ(result.draws, 3u);
  EXPECT_EQ(result.distinctPairs, 1u);
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.source, "uniform clipFromWorld (program 1)");
  EXPECT_EQ(group.first.frame, 0u);
  EXPECT_EQ(group.first.call, 49u);
  EXPECT_EQ(group.last.frame, 2u);
  EXPECT_EQ(group.last.call, 57u);
  EXPECT_EQ(group.draws, 3u);
  EXPECT_TRUE(group.depth.clipZeroToOne);
  EXPECT_EQ(group.depth.clipControlCall, 23u);
  EXPECT_EQ(group.depth.depthFormatName, "32f");
  EXPECT_EQ(group.depth.viewport, (Viewport{64, 48}));
  EXPECT_EQ(group.report.properties.builtFor, "no");
  EXPECT_EQ(codes(group), std::vector<std::string>{"error:depth-convention-mismatch"});
  EXPECT_NEAR(group.report.properties.nearIfBuiltForZo->value, 0.1998, 1e-4);
  EXPECT_TRUE(result.hasErrors());
  EXPECT_TRUE(result.findings.empty());
}

TEST(TraceCheck, CapturedFixedFunctionFrustum) {
  const TraceCheckResult result = checkLines(captured("fixed-function-frustum-under-zo.dump.txt"));
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.source, "fixed-function GL_PROJECTION");
  EXPECT_EQ(group.depth.depthFunc, kGlLequal);
  // glFrustum(near 0.1, far 100), rounded to float as the driver stores it.
  EXPECT_EQ(group.matrix[3][2], static_cast<double>(static_cast<float>(-200.0 * 0.1f / 99.9f)));
  EXPECT_EQ(group.matrix[2][3], -1.0);
  EXPECT_EQ(group.report.properties.builtFor, "no");
  EXPECT_EQ(codes(group), std::vector<std::string>{"error:depth-convention-mismatch"});
}

TEST(TraceCheck, FrameRangeSelectsDraws) {
  const TraceCheckResult result = checkLines(captured("no-under-zo.dump.txt"), {1, 1});
  EXPECT_EQ(result.draws, 1u);
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].first.call, 53u);
  EXPECT_EQ(result.groups[0].last.call, 53u);
  EXPECT_EQ(
      refusal(captured("no-under-zo.dump.txt"), {5, 9}),
      "app.trace: no GL draw calls in frames 5-9 (59 calls in 3 frames read): nothing to check");
}

TEST(TraceCheck, ReversedMatrixWithLessAndClearOne) {
  // Reversed-Z, infinite far (near 0.1): z_clip = 0.1, w_clip = -z_view.
  const std::string reversed = "{1.299038, 0, 0, 0, 0, 1.732051, 0, 0, 0, 0, 0, -1, 0, 0, 0.1, 0}";
  const TraceCheckResult result = checkLines(
      shaderApp("3 glClipControl(origin = GL_LOWER_LEFT, depth = GL_ZERO_TO_ONE)\n"
                "4 glDepthFunc(func = GL_LESS)\n",
                "glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
                "glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
                    reversed +
                    ")\n"
                    "glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)",
                2));
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(codes(group),
            (std::vector<std::string>{"error:reversed-z-mismatch", "warning:infinite-far-plane",
                                      "error:clear-depth-mismatch"}));
  EXPECT_NE(group.report.findings[0].message.find("(traced: glDepthFunc(GL_LESS) at call 4)"),
            std::string::npos)
      << group.report.findings[0].message;
  EXPECT_EQ(group.report.findings[2].message,
            "the depth buffer is cleared to 1 (call 20), the far value of the classic "
            "convention; this matrix puts far at 0, so the cleared depth is nearer than any "
            "surface and nothing passes the test");
  EXPECT_EQ(group.first.call, 22u);
  EXPECT_EQ(group.last.call, 26u);
}

TEST(TraceCheck, TransposeFlagAndProgramUniforms) {
  // The same NO matrix, listed row by row and uploaded with transpose = GL_TRUE: correct.
  const std::string rowByRow =
      "{1.299038, 0, 0, 0, 0, 1.608169, -0.6432676, 0, 0, -0.3721342, -0.9303355, 5.195746, 0, "
      "-0.3713907, -0.9284767, 5.385165}";
  const TraceCheckResult result = checkLines(shaderApp(
      "4 glDepthFunc(func = GL_LESS)\n",
      "glProgramUniformMatrix4fv(program = 1, location = 0, count = 1, transpose = GL_TRUE, "
      "value = " +
          rowByRow +
          ")\n"
          "glDrawElements(mode = GL_TRIANGLES, count = 3, type = GL_UNSIGNED_SHORT, indices = "
          "NULL)",
      1));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].report.properties.builtFor, "no");
  EXPECT_TRUE(result.groups[0].report.findings.empty());
  EXPECT_FALSE(result.hasErrors());
}

TEST(TraceCheck, ProgramPipelinesReadTheVertexStagesUniforms) {
  // Separable programs: program 2 is pipeline 1's vertex stage, program 3 its fragment stage
  // (whose matrix is no camera's). The vertex stage's matrix arrives through
  // glActiveShaderProgram + glUniformMatrix4fv; glUseProgram's program takes precedence over the
  // pipeline while it is bound, and glUseProgram(0) hands the draws back to the pipeline.
  const std::string text =
      "1 glViewport(x = 0, y = 0, width = 64, height = 48)\n"
      "2 glEnable(cap = GL_DEPTH_TEST)\n"
      "3 glClipControl(origin = GL_LOWER_LEFT, depth = GL_ZERO_TO_ONE)\n"
      "4 glDepthFunc(func = GL_LESS)\n"
      "5 glGetUniformLocation(program = 2, name = \"clipFromWorld\") = 0\n"
      "6 glUseProgramStages(pipeline = 1, stages = GL_VERTEX_SHADER_BIT, program = 2)\n"
      "7 glUseProgramStages(pipeline = 1, stages = GL_FRAGMENT_SHADER_BIT, program = 3)\n"
      "8 glBindProgramPipeline(pipeline = 1)\n"
      "9 glProgramUniformMatrix4fv(program = 3, location = 0, count = 1, transpose = GL_FALSE, "
      "value = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -1, 0, 0, 2, 0})\n"
      "10 glActiveShaderProgram(pipeline = 1, program = 2)\n"
      "11 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
      kNoMatrix +
      ")\n"
      "12 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
      "13 glUseProgram(program = 4)\n"
      "14 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
      "15 glUseProgram(program = 0)\n"
      "16 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
      "17 eglSwapBuffers(dpy = 0x1, surface = 0x2) = EGL_TRUE\n";
  const TraceCheckResult result = checkLines(text);
  EXPECT_EQ(result.draws, 3u);
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.source, "uniform clipFromWorld (program 2)");
  EXPECT_EQ(group.draws, 2u);
  EXPECT_EQ(group.first.call, 12u);
  EXPECT_EQ(group.last.call, 16u);
  EXPECT_EQ(group.report.properties.builtFor, "no");
  EXPECT_EQ(codes(group), std::vector<std::string>{"error:depth-convention-mismatch"});
  // GL_ALL_SHADER_BITS holds the vertex stage too.
  std::string allStages = text;
  allStages.replace(allStages.find("GL_VERTEX_SHADER_BIT"), 20, "GL_ALL_SHADER_BITS");
  const TraceCheckResult all = checkLines(allStages);
  ASSERT_EQ(all.groups.size(), 1u);
  EXPECT_EQ(all.groups[0].source, "uniform clipFromWorld (program 2)");
}

TEST(TraceCheck, ReversedDepthRangeWithClassicMatrix) {
  // osgfpdepth's inverted depth: osg::Depth(GEQUAL, 1, 0) and clear 0 under NEGATIVE_ONE_TO_ONE.
  // One cause, one warning: the depth range's, with its call (the matrix check's
  // reversed-z-without-zero-to-one would say the same without it).
  const TraceCheckResult result = checkLines(
      shaderApp("4 glDepthFunc(func = GL_GREATER)\n5 glDepthRange(zNear = 1, zFar = 0)\n"
                "6 glClearDepth(depth = 0)\n",
                "glClear(mask = GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT)\n"
                "glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
                    kNoMatrix +
                    ")\n"
                    "glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)",
                1));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(codes(result.groups[0]), std::vector<std::string>{"warning:depth-range-reversed"});
  EXPECT_EQ(result.groups[0].report.findings[0].message,
            "glDepthRange(1, 0) (call 5) reverses window depth under a classic matrix: "
            "reversed-Z by depth range keeps float depth precise only under ZERO_TO_ONE, where "
            "the matrix itself can be reversed");
}

// kNoMatrix built y-down, as a Direct3D/Vulkan-style app builds it for GL_UPPER_LEFT.
const std::string kYFlippedNoMatrix =
    "{1.299038, -0, 0, 0, 0, -1.608169, -0.3721342, -0.3713907, 0, 0.6432676, -0.9303355, "
    "-0.9284767, 0, -0, 5.195746, 5.385165}";

TracePairGroup culledDraw(const std::string& setup, const std::string& matrix) {
  const TraceCheckResult result = checkLines(
      shaderApp(setup,
                "glClear(mask = GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT)\n"
                "glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
                    matrix +
                    ")\n"
                    "glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)",
                1));
  CLIPRAY_CHECK(result.groups.size() == 1u, "one (matrix, state) pair");
  return result.groups[0];
}

// The classic mistake: a y-flipped projection under GL_UPPER_LEFT with back-face culling and
// glFrontFace left at GL_CCW keeps the insides; GL_CW (or a projection that is not flipped) does
// not; GL_FRONT with GL_CW is the same mistake the other way round.
TEST(TraceCheck, FaceCullingUnderAYFlipIsNamed) {
  const std::string upperLeft =
      "3 glClipControl(origin = GL_UPPER_LEFT, depth = GL_NEGATIVE_ONE_TO_ONE)\n";
  const TracePairGroup flipped =
      culledDraw(upperLeft + "4 glEnable(cap = GL_CULL_FACE)\n", kYFlippedNoMatrix);
  ASSERT_EQ(codes(flipped),
            (std::vector<std::string>{"info:y-flipped", "warning:face-culling-keeps-insides"}));
  EXPECT_EQ(flipped.report.findings[1].message,
            "face culling (glCullFace(GL_BACK) at call 4, glFrontFace(GL_CCW) at GL's default) "
            "keeps the triangles that wind clockwise seen from the eye: the matrix flips y, as a "
            "projection built for glClipControl(GL_UPPER_LEFT) does; the origin turns the picture "
            "upright but GL keeps clip space's winding. Meshes wound counter-clockwise seen from "
            "outside (glTF, OBJ, GL's default) show their insides");
  EXPECT_EQ(flipped.report.findings[1].fix,
            "glFrontFace(GL_CW) while this matrix is in force (nothing, if the meshes are wound "
            "clockwise seen from outside)");
  EXPECT_EQ(codes(culledDraw(upperLeft + "4 glEnable(cap = GL_CULL_FACE)\n"
                                         "5 glFrontFace(mode = GL_CW)\n",
                             kYFlippedNoMatrix)),
            std::vector<std::string>{"info:y-flipped"});
  EXPECT_TRUE(codes(culledDraw("4 glEnable(cap = GL_CULL_FACE)\n", kNoMatrix)).empty());
  // Culling enabled and then disabled again: nothing is culled at the draw.
  EXPECT_EQ(codes(culledDraw(upperLeft + "4 glEnable(cap = GL_CULL_FACE)\n"
                                         "5 glDisable(cap = GL_CULL_FACE)\n",
                             kYFlippedNoMatrix)),
            std::vector<std::string>{"info:y-flipped"});
  const TracePairGroup front = culledDraw(upperLeft +
                                              "4 glEnable(cap = GL_CULL_FACE)\n"
                                              "5 glCullFace(mode = GL_FRONT)\n"
                                              "6 glFrontFace(mode = GL_CW)\n",
                                          kYFlippedNoMatrix);
  ASSERT_EQ(codes(front),
            (std::vector<std::string>{"info:y-flipped", "warning:face-culling-keeps-insides"}));
  EXPECT_EQ(front.report.findings[1].message.substr(0, 100),
            "face culling (glCullFace(GL_FRONT) at call 5, glFrontFace(GL_CW) at call 6) keeps the "
            "triangles that");
  EXPECT_EQ(front.report.findings[1].fix.substr(0, 18), "glFrontFace(GL_CCW");
}

TEST(TraceCheck, ProjectionChangingWithinAFrameIsANote) {
  // Two cameras in one frame: the NO matrix, then the same with another aspect.
  const std::string other =
      "{0.974279, 0, 0, 0, 0, 1.608169, -0.3721342, -0.3713907, 0, -0.6432676, -0.9303355, "
      "-0.9284767, 0, 0, 5.195746, 5.385165}";
  const std::string draw = "glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n";
  const std::string upload =
      "glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = ";
  const TraceCheckResult result =
      checkLines(shaderApp("4 glDepthFunc(func = GL_LESS)\n",
                           upload + kNoMatrix + ")\n" + draw + upload + other + ")\n" + draw, 3));
  EXPECT_EQ(result.distinctPairs, 2u);
  // Both read alike (built for NO, no findings): one group of two matrices.
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].distinctMatrices, 2u);
  EXPECT_EQ(result.groups[0].draws, 6u);
  EXPECT_EQ(result.groups[0].first.call, 21u);
  EXPECT_EQ(result.groups[0].last.frame, 2u);
  ASSERT_EQ(result.findings.size(), 1u);
  EXPECT_EQ(result.findings[0].code, "projection-changes-within-frame");
  EXPECT_EQ(result.findings[0].severity, "info");
  EXPECT_EQ(result.findings[0].message,
            "a projective matrix changes between draws of one frame in 3 frame(s) (first: frame "
            "0, uniform clipFromWorld (program 1), at call 23): per-object MVPs, or a second "
            "camera (shadow map, UI)");
}

TEST(TraceCheck, FixedFunctionStackOrthoPushPop) {
  const TraceCheckResult result = checkLines(
      "1 glMatrixMode(mode = GL_PROJECTION)\n2 glLoadIdentity()\n"
      "3 glOrtho(left = -2, right = 2, bottom = -1.5, top = 1.5, zNear = 1, zFar = 11)\n"
      "4 glPushMatrix()\n5 glScalef(x = 9, y = 9, z = 9)\n6 glPopMatrix()\n"
      "7 glMatrixMode(mode = GL_MODELVIEW)\n8 glTranslatef(x = 0, y = 0, z = -5)\n"
      "9 glBegin(mode = GL_TRIANGLES)\n10 glEnd()\n");
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.matrix[0][0], 0.5);
  EXPECT_EQ(group.matrix[2][2], static_cast<double>(-0.2f));
  EXPECT_EQ(group.matrix[3][2], static_cast<double>(-1.2f));
  EXPECT_FALSE(group.report.properties.perspective);
  EXPECT_FALSE(group.depth.depthTest);
}

// glOrtho(-1, 1, -1, 1, -1, 1), the unit cube: once missed as a mirror, now a projection whose
// NO/ZO reading is open (near -1 or 0 around the camera), so the ZO state gives no error.
TEST(TraceCheck, CubeOrthoIsAProjectionLeftAmbiguous) {
  const TraceCheckResult result = checkLines(
      "1 glClipControl(origin = GL_LOWER_LEFT, depth = GL_ZERO_TO_ONE)\n"
      "2 glMatrixMode(mode = GL_PROJECTION)\n3 glLoadIdentity()\n"
      "4 glOrtho(left = -1, right = 1, bottom = -1, top = 1, zNear = -1, zFar = 1)\n"
      "5 glBegin(mode = GL_TRIANGLES)\n6 glEnd()\n");
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.source, "fixed-function GL_PROJECTION");
  EXPECT_EQ(group.matrix[2][2], -1.0);
  EXPECT_EQ(group.report.properties.builtFor, "ambiguous");
  EXPECT_EQ(codes(group), std::vector<std::string>{"info:depth-convention-ambiguous"});
  EXPECT_FALSE(result.hasErrors());
}

// The depth format of a depth texture attachment: level 0's internalformat from glTexImage2D /
// glTexStorage* on the texture bound to that unit and target (cube faces set the cube map), or
// glTextureStorage* by name; an unsized GL_DEPTH_COMPONENT stays unknown.
TEST(TraceCheck, DepthTextureFormats) {
  const std::string frustum =
      "3 glMatrixMode(mode = GL_PROJECTION)\n"
      "4 glFrustum(left = -1, right = 1, bottom = -1, top = 1, zNear = 5, zFar = 60)\n";
  const auto formatAfter = [&](const std::string& setup) {
    const TraceCheckResult result =
        checkLines("1 glBindFramebuffer(target = GL_FRAMEBUFFER, framebuffer = 3)\n" + frustum +
                   setup + "90 glBegin(mode = GL_TRIANGLES)\n");
    return result.groups.empty() ? std::string("(no group)")
                                 : result.groups[0].depth.depthFormatName;
  };
  EXPECT_EQ(
      formatAfter("10 glActiveTexture(texture = GL_TEXTURE1)\n"
                  "11 glBindTexture(target = GL_TEXTURE_2D, texture = 7)\n"
                  "12 glActiveTexture(texture = GL_TEXTURE0)\n"
                  "13 glBindTexture(target = GL_TEXTURE_2D, texture = 8)\n"
                  "14 glTexImage2D(target = GL_TEXTURE_2D, level = 0, internalformat = "
                  "GL_DEPTH_COMPONENT16, width = 64, height = 48, border = 0, format = "
                  "GL_DEPTH_COMPONENT, type = GL_UNSIGNED_SHORT, pixels = NULL)\n"
                  "15 glTexImage2D(target = GL_TEXTURE_2D, level = 1, internalformat = "
                  "GL_DEPTH_COMPONENT32F, width = 32, height = 24, border = 0, format = "
                  "GL_DEPTH_COMPONENT, type = GL_FLOAT, pixels = NULL)\n"
                  "16 glFramebufferTexture2D(target = GL_FRAMEBUFFER, attachment = "
                  "GL_DEPTH_ATTACHMENT, textarget = GL_TEXTURE_2D, texture = 8, level = 0)\n"),
      "16");
  // Texture 7 on unit 1 got nothing: its format is unknown.
  EXPECT_EQ(formatAfter("11 glActiveTexture(texture = GL_TEXTURE1)\n"
                        "12 glBindTexture(target = GL_TEXTURE_2D, texture = 7)\n"
                        "13 glActiveTexture(texture = GL_TEXTURE0)\n"
                        "14 glTexStorage2D(target = GL_TEXTURE_2D, levels = 1, internalformat = "
                        "GL_DEPTH32F_STENCIL8, width = 64, height = 48)\n"
                        "16 glFramebufferTexture(target = GL_DRAW_FRAMEBUFFER, attachment = "
                        "GL_DEPTH_STENCIL_ATTACHMENT, texture = 7, level = 0)\n"),
            "unknown");
  EXPECT_EQ(formatAfter("12 glBindTexture(target = GL_TEXTURE_CUBE_MAP, texture = 5)\n"
                        "13 glTexImage2D(target = GL_TEXTURE_CUBE_MAP_POSITIVE_X, level = 0, "
                        "internalformat = GL_DEPTH_COMPONENT32F, width = 64, height = 64, border "
                        "= 0, format = GL_DEPTH_COMPONENT, type = GL_FLOAT, pixels = NULL)\n"
                        "16 glFramebufferTexture2D(target = GL_FRAMEBUFFER, attachment = "
                        "GL_DEPTH_ATTACHMENT, textarget = GL_TEXTURE_CUBE_MAP_POSITIVE_X, texture "
                        "= 5, level = 0)\n"),
            "32f");
  EXPECT_EQ(formatAfter("14 glTextureStorage3D(texture = 4, levels = 1, internalformat = "
                        "GL_DEPTH24_STENCIL8, width = 64, height = 64, depth = 4)\n"
                        "16 glNamedFramebufferTextureLayer(framebuffer = 3, attachment = "
                        "GL_DEPTH_ATTACHMENT, texture = 4, level = 0, layer = 2)\n"),
            "24");
  EXPECT_EQ(
      formatAfter("12 glBindTexture(target = GL_TEXTURE_2D, texture = 8)\n"
                  "13 glTexImage2D(target = GL_TEXTURE_2D, level = 0, internalformat = "
                  "GL_DEPTH_COMPONENT, width = 64, height = 48, border = 0, format = "
                  "GL_DEPTH_COMPONENT, type = GL_FLOAT, pixels = NULL)\n"
                  "16 glFramebufferTexture2D(target = GL_FRAMEBUFFER, attachment = "
                  "GL_DEPTH_ATTACHMENT, textarget = GL_TEXTURE_2D, texture = 8, level = 0)\n"),
      "unknown");
}

// A block that cannot be read is a note about the trace, beside the matrices that can.
TEST(TraceCheck, UnreadUniformBlockIsANote) {
  const TraceCheckResult result = checkLines(
      "2 glShaderSource(shader = 2, count = 1, string = &\"uniform Shared { mat4 m; };\\nuniform "
      "mat4 clipFromWorld;\\n\", length = NULL)\n3 glAttachShader(program = 1, shader = 2)\n"
      "4 glLinkProgram(program = 1)\n5 glUseProgram(program = 1)\n"
      "6 glGetUniformLocation(program = 1, name = \"clipFromWorld\") = 0\n"
      "7 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
      kNoMatrix + ")\n8 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n");
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source, "uniform clipFromWorld (program 1)");
  ASSERT_EQ(result.findings.size(), 1u);
  EXPECT_EQ(result.findings[0].severity, "info");
  EXPECT_EQ(result.findings[0].code, "uniform-block-not-read");
  EXPECT_EQ(result.findings[0].message,
            "ubo Shared (program 1): shared layout: its offsets are the implementation's "
            "(apitrace records an app's GL_UNIFORM_OFFSET query without its result), so its "
            "matrices are not read (first at the draw at call 8)");
}

TEST(TraceCheck, DrawsCompiledIntoADisplayListAreNotDraws) {
  // As glxgears builds its gears: glBegin inside glNewList(GL_COMPILE) only records.
  const TraceCheckResult result = checkLines(
      "1 glNewList(list = 1, mode = GL_COMPILE)\n2 glBegin(mode = GL_QUAD_STRIP)\n3 glEnd()\n"
      "4 glEndList()\n5 glMatrixMode(mode = GL_PROJECTION)\n"
      "6 glFrustum(left = -1, right = 1, bottom = -1, top = 1, zNear = 5, zFar = 60)\n"
      "7 glCallList(list = 1)\n");
  EXPECT_EQ(result.draws, 1u);
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].first.call, 7u);
  EXPECT_NEAR(result.groups[0].report.properties.near->value, 5.0, 1e-5);
  EXPECT_NEAR(result.groups[0].report.properties.far->value, 60.0, 1e-3);
}

TEST(TraceCheck, ShadowMapLookUpMatrixIsANote) {
  // glmark2's shadow scene: LightMatrix = translate(0.5) * scale(0.5) * perspective(NO, near 2,
  // far 50) * lookAt((0, 3, 2), 0, +Y), as apitrace traced it (glmark2 2023.01, 320x240).
  const std::string lightMatrix =
      "{1.041002, 0, 0, 0, -0.4160252, 0.3539003, -0.8667191, -0.8320503, -0.2773501, "
      "-1.432238, -0.5778127, -0.5547002, 1.802776, 1.802776, 1.67245, 3.605551}";
  const TraceCheckResult result = checkLines(shaderApp(
      "4 glDepthFunc(func = GL_LEQUAL)\n",
      "glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " + lightMatrix +
          ")\nglDrawArrays(mode = GL_TRIANGLE_STRIP, first = 0, count = 4)",
      1));
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(codes(group), std::vector<std::string>{"info:texture-space-matrix"});
  EXPECT_EQ(group.report.properties.builtFor, "no");
  EXPECT_NEAR(group.report.properties.nearIfBuiltForNo->value, 2.0, 1e-4);
  EXPECT_FALSE(result.hasErrors());
}

TEST(TraceCheck, UniformNamesStayPrintable) {
  // Found by fuzzing the reader: a damaged name's bytes made the JSON report throw.
  const TraceCheckResult result = checkLines(
      "1 glUseProgram(program = 1)\n2 glGetUniformLocation(program = 1, name = \"mvp\\254\\n\") "
      "= 0\n3 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
      kNoMatrix + ")\n4 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n");
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source, "uniform mvp?? (program 1)");
  EXPECT_NO_THROW((void)traceCheckJson(result).dump());
}

TEST(TraceCheck, BadTracesAreRefusedWithOneLine) {
  EXPECT_EQ(refusal(""), "app.trace: no calls: not an apitrace trace, or an empty one");
  EXPECT_EQ(refusal("// process.name = \"/tmp/app\"\n1 glFinish()\n"
                    "warning: unexpected end of file while reading trace\n"),
            "app.trace: truncated trace (apitrace: unexpected end of file while reading trace)");
  EXPECT_EQ(refusal("error: failed to open app.trace\n"),
            "app.trace: apitrace: failed to open app.trace");
  EXPECT_EQ(refusal("1 eglSwapBuffers(dpy = 0x1, surface = 0x2) = EGL_TRUE\n"),
            "app.trace: no GL draw calls (1 calls in 1 frames read): nothing to check");
  EXPECT_EQ(refusal("1 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"),
            "app.trace: none of the 1 draws has a matrix with a projection's structure (uniform "
            "mat4, std140 uniform block mat4 or fixed-function GL_PROJECTION)");
  // A camera block that cannot be read says why.
  EXPECT_EQ(refusal("1 glShaderSource(shader = 2, count = 1, string = &\"uniform Camera { mat4 "
                    "clipFromWorld; };\", length = NULL)\n2 glAttachShader(program = 1, shader = "
                    "2)\n3 glLinkProgram(program = 1)\n4 glUseProgram(program = 1)\n5 "
                    "glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"),
            "app.trace: none of the 1 draws has a matrix with a projection's structure (uniform "
            "mat4, std140 uniform block mat4 or fixed-function GL_PROJECTION); not read: ubo "
            "Camera (program 1): shared layout: its offsets are the implementation's (apitrace "
            "records an app's GL_UNIFORM_OFFSET query without its result), so its matrices are "
            "not read (first at the draw at call 5)");
  EXPECT_EQ(refusal("1 glDepthFunc(func = GL_LESS\n"),
            "app.trace: call 1 (glDepthFunc): column 29: expected ','");
  EXPECT_EQ(refusal("1 glViewport(x = 0, y = 0, width = wide, height = 48)\n"),
            "app.trace: call 1 (glViewport): glViewport: width = wide is not a number");
  EXPECT_EQ(refusal("1 glViewport(x = 0, y = 0, width = 1e300, height = 48)\n"),
            "app.trace: call 1 (glViewport): glViewport: width = 1e300 is not an integer in "
            "range");
  EXPECT_EQ(refusal("1 glUseProgram(program = -1)\n"),
            "app.trace: call 1 (glUseProgram): glUseProgram: program = -1 is not an integer in "
            "range");
  EXPECT_EQ(refusal("1 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
                    std::string(40, '{') + ")\n"),
            "app.trace: call 1 (glUniformMatrix4fv): column 110: values nested deeper than 32");
}

TEST(TraceCheck, FramesOption) {
  EXPECT_EQ(parseFrameRange("3-7").first, 3u);
  EXPECT_EQ(parseFrameRange("3-7").last, 7u);
  EXPECT_EQ(parseFrameRange("4").last, 4u);
  for (const std::string bad : {"7-3", "a-b", "-3", "3-", ""}) {
    try {
      parseFrameRange(bad);
      FAIL() << bad;
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()),
                "--frames: expected A-B or A (frame numbers from 0, A <= B), got \"" + bad + "\"");
    }
  }
}

}  // namespace
}  // namespace clipray::trace

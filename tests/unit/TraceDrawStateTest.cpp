// The state `clipray check --trace` follows per draw beyond the depth test and culling
// (trace/GlTraceState.*): GL_DEPTH_CLAMP and GL_CLIP_DISTANCEi with the shaders that write
// gl_ClipDistance, glPushAttrib/glPopAttrib, glDepthRange clamped as GL clamps it, evaluator
// draws, and the glEnd a replay dumps a glBegin's depth at. Fed as written dump text.

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/trace/TraceCheck.hpp"
#include "support/TraceLines.hpp"

namespace clipray::trace {
namespace {

using testing::checkLines;
using testing::codes;

// The depth state line of a group's text report.
std::string depthStateLine(const TraceCheckResult& result, std::size_t group) {
  std::istringstream text(traceCheckText(result));
  std::string line;
  std::size_t seen = 0;
  while (std::getline(text, line)) {
    if (line.starts_with("  depth state: ") && seen++ == group) return line.substr(15);
  }
  return "(none)";
}

// glm::perspectiveRH_NO(60 deg, 4/3, 0.1, 100) * lookAtRH((0, 2, 5), 0, +Y) in float, as
// apitrace writes it (7 significant digits).
const std::string kNoMatrix =
    "{1.299038, 0, 0, 0, 0, 1.608169, -0.3721342, -0.3713907, 0, -0.6432676, -0.9303355, "
    "-0.9284767, 0, 0, 5.195746, 5.385165}";

const std::string kProgram =
    "1 glViewport(x = 0, y = 0, width = 64, height = 48)\n"
    "2 glEnable(cap = GL_DEPTH_TEST)\n"
    "3 glUseProgram(program = 1)\n"
    "4 glGetUniformLocation(program = 1, name = \"clipFromWorld\") = 0\n"
    "5 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
    kNoMatrix + ")\n";

// glFrustum(-1, 1, -0.75, 0.75, 1, 50) on the fixed-function projection stack.
const std::string kFrustum =
    "1 glMatrixMode(mode = GL_PROJECTION)\n"
    "2 glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, zNear = 1, zFar = 50)\n"
    "3 glMatrixMode(mode = GL_MODELVIEW)\n";

TEST(TraceDrawState, DepthClampAndClipDistancesPerDraw) {
  const TraceCheckResult result =
      checkLines(kProgram +
                 "6 glEnable(cap = GL_DEPTH_CLAMP)\n"
                 "7 glEnable(cap = GL_CLIP_DISTANCE0)\n"
                 "8 glEnable(cap = GL_CLIP_PLANE2)\n"  // GL 1.0's name for GL_CLIP_DISTANCE2
                 "9 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
                 "10 glDisable(cap = GL_DEPTH_CLAMP)\n"
                 "11 glDisable(cap = GL_CLIP_DISTANCE0)\n"
                 "12 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n");
  ASSERT_EQ(result.groups.size(), 2u);
  const TracePairGroup& clamped = result.groups[0];
  EXPECT_TRUE(clamped.depth.depthClamp);
  EXPECT_EQ(clamped.depth.depthClampCall, 6u);
  EXPECT_EQ(clamped.depth.clipDistances, 0b101u);
  EXPECT_EQ(clamped.depth.clipDistancesCall, 8u);
  EXPECT_EQ(depthStateLine(result, 0),
            "clip control lower-left, negative-one-to-one; depth test GL_LESS; depth range 0, 1; "
            "cleared to -; viewport 64x48; depth buffer unknown; depth clamp on; clip distances "
            "0, 2 enabled");
  ASSERT_EQ(codes(clamped), std::vector<std::string>{"info:depth-clamp-near-plane"});
  EXPECT_EQ(clamped.report.findings[0].message,
            "GL_DEPTH_CLAMP is on (glEnable(GL_DEPTH_CLAMP) at call 6): nothing is clipped at "
            "the near plane; a surface between the eye and the near plane (0.0999999) is drawn "
            "at window depth 0, the near plane's, so a picking ray that starts on the near plane "
            "cannot hit it and unprojecting the depth buffer there gives a point on the near "
            "plane, not on the surface; likewise a surface beyond the far plane (100) is "
            "drawn at window depth 1, past the end of a ray bounded by it");
  const TracePairGroup& unclamped = result.groups[1];
  EXPECT_FALSE(unclamped.depth.depthClamp);
  EXPECT_EQ(unclamped.depth.clipDistances, 0b100u);
  EXPECT_TRUE(codes(unclamped).empty());
  EXPECT_EQ(depthStateLine(result, 1),
            "clip control lower-left, negative-one-to-one; depth test GL_LESS; depth range 0, 1; "
            "cleared to -; viewport 64x48; depth buffer unknown; clip distance 2 enabled");
  const nlohmann::json json = traceCheckJson(result);
  const nlohmann::json& state = json["groups"][0]["depth_state"];
  EXPECT_EQ(state["depth_clamp"], true);
  EXPECT_EQ(state["clip_distances"], nlohmann::json({0, 2}));
  EXPECT_EQ(state["writes_clip_distance"], false);
  EXPECT_EQ(state["calls"]["depth_clamp"], 6);
  EXPECT_EQ(state["calls"]["clip_distances"], 8);
  EXPECT_EQ(json["groups"][1]["depth_state"]["depth_clamp"], false);
}

TEST(TraceDrawState, ShadersThatWriteClipDistances) {
  // Program 1's vertex shader writes gl_ClipDistance[0]; program 2 names it in a comment only.
  const std::string text =
      "1 glShaderSource(shader = 5, count = 1, string = &\"void main() { gl_Position = vec4(0); "
      "gl_ClipDistance[0] = 1.0; }\", length = NULL)\n"
      "2 glAttachShader(program = 1, shader = 5)\n3 glLinkProgram(program = 1)\n"
      "4 glShaderSource(shader = 6, count = 1, string = &\"// gl_ClipDistance: not here\\nvoid "
      "main() { gl_Position = vec4(0); }\", length = NULL)\n"
      "5 glAttachShader(program = 2, shader = 6)\n6 glLinkProgram(program = 2)\n"
      "7 glGetUniformLocation(program = 1, name = \"mvp\") = 0\n"
      "8 glGetUniformLocation(program = 2, name = \"mvp\") = 0\n"
      "9 glProgramUniformMatrix4fv(program = 1, location = 0, count = 1, transpose = GL_FALSE, "
      "value = " +
      kNoMatrix +
      ")\n10 glProgramUniformMatrix4fv(program = 2, location = 0, count = 1, transpose = "
      "GL_FALSE, value = " +
      kNoMatrix +
      ")\n11 glUseProgram(program = 1)\n"
      "12 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
      "13 glEnable(cap = GL_CLIP_DISTANCE0)\n"
      "14 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
      "15 glUseProgram(program = 2)\n"
      "16 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n";
  const TraceCheckResult result = checkLines(text);
  ASSERT_EQ(result.groups.size(), 3u);
  EXPECT_TRUE(result.groups[0].depth.writesClipDistance);
  EXPECT_TRUE(depthStateLine(result, 0).ends_with(
      "; the program writes gl_ClipDistance, but no GL_CLIP_DISTANCEi is "
      "enabled"))
      << depthStateLine(result, 0);
  EXPECT_TRUE(depthStateLine(result, 1).ends_with(
      "; clip distance 0 enabled (the program writes gl_ClipDistance)"))
      << depthStateLine(result, 1);
  EXPECT_FALSE(result.groups[2].depth.writesClipDistance);
  EXPECT_TRUE(depthStateLine(result, 2).ends_with("; clip distance 0 enabled"));
}

// glDepthMask is followed (for what a replayed draw left in the depth buffer) and is part of
// GL_DEPTH_BUFFER_BIT, not of GL_ENABLE_BIT; it does not split a group.
TEST(TraceDrawState, DepthMaskFollowedThroughTheAttributeStack) {
  const auto firstDraw = [](const std::string& pushed) {
    const TraceCheckResult result =
        checkLines(kFrustum + "4 glEnable(cap = GL_DEPTH_TEST)\n5 glPushAttrib(mask = " + pushed +
                   ")\n6 glDepthMask(flag = GL_FALSE)\n7 glPopAttrib()\n"
                   "8 glBegin(mode = GL_QUADS)\n9 glEnd()\n"
                   "10 glDepthMask(flag = GL_TRUE)\n11 glBegin(mode = GL_QUADS)\n12 glEnd()\n");
    EXPECT_EQ(result.groups.size(), 1u);
    return result.groups.empty() ? TraceDepthState{} : result.groups[0].depth;
  };
  const TraceDepthState restored = firstDraw("GL_DEPTH_BUFFER_BIT");
  EXPECT_TRUE(restored.depthWrite);
  EXPECT_EQ(restored.depthMaskCall, 0u);
  const TraceDepthState kept = firstDraw("GL_ENABLE_BIT");
  EXPECT_FALSE(kept.depthWrite);
  EXPECT_EQ(kept.depthMaskCall, 6u);
}

TEST(TraceDrawState, PushAttribRestoresTheGroupsPushed) {
  const TraceCheckResult result = checkLines(
      kFrustum +
      "4 glEnable(cap = GL_DEPTH_TEST)\n"
      "5 glDepthFunc(func = GL_LEQUAL)\n"
      "6 glPushAttrib(mask = GL_ENABLE_BIT | GL_VIEWPORT_BIT)\n"
      "7 glPushAttrib(mask = GL_DEPTH_BUFFER_BIT)\n"
      "8 glDisable(cap = GL_DEPTH_TEST)\n"
      "9 glDepthFunc(func = GL_ALWAYS)\n"
      "10 glEnable(cap = GL_DEPTH_CLAMP)\n"
      "11 glDepthRange(zNear = 0.5, zFar = 1)\n"
      "12 glBegin(mode = GL_QUADS)\n13 glEnd()\n"
      // GL_DEPTH_BUFFER_BIT: the test and its func come back, the clamp (enable, transform) not.
      "14 glPopAttrib()\n"
      "15 glBegin(mode = GL_QUADS)\n16 glEnd()\n"
      // GL_ENABLE_BIT | GL_VIEWPORT_BIT: the clamp and the depth range come back.
      "17 glPopAttrib()\n"
      "18 glBegin(mode = GL_QUADS)\n19 glEnd()\n"
      // A pop with nothing pushed is a GL error: no effect.
      "20 glPopAttrib()\n"
      "21 glPushAttrib(mask = 0x2000)\n"  // GL_ENABLE_BIT as a number
      "22 glDisable(cap = GL_DEPTH_TEST)\n23 glPopAttrib()\n"
      "24 glPushAttrib(mask = GL_CURRENT_BIT)\n"
      "25 glDisable(cap = GL_DEPTH_TEST)\n26 glPopAttrib()\n"
      "27 glBegin(mode = GL_QUADS)\n28 glEnd()\n");
  ASSERT_EQ(result.groups.size(), 4u);
  const TraceDepthState& inside = result.groups[0].depth;
  EXPECT_FALSE(inside.depthTest);
  EXPECT_EQ(inside.depthFunc, kGlAlways);
  EXPECT_TRUE(inside.depthClamp);
  EXPECT_EQ(inside.depthRange, glm::dvec2(0.5, 1.0));
  const TraceDepthState& afterDepthPop = result.groups[1].depth;
  EXPECT_TRUE(afterDepthPop.depthTest);
  EXPECT_EQ(afterDepthPop.depthFunc, kGlLequal);
  EXPECT_EQ(afterDepthPop.depthFuncCall, 5u);
  EXPECT_TRUE(afterDepthPop.depthClamp);
  EXPECT_EQ(afterDepthPop.depthRange, glm::dvec2(0.5, 1.0));
  const TraceDepthState& afterEnablePop = result.groups[2].depth;
  EXPECT_TRUE(afterEnablePop.depthTest);
  EXPECT_FALSE(afterEnablePop.depthClamp);
  EXPECT_EQ(afterEnablePop.depthRange, glm::dvec2(0.0, 1.0));
  EXPECT_EQ(afterEnablePop.depthRangeCall, 0u);
  EXPECT_EQ(result.groups[2].first.call, 18u);
  // The numeric GL_ENABLE_BIT push restored the test; GL_CURRENT_BIT's did not.
  EXPECT_FALSE(result.groups[3].depth.depthTest);
  EXPECT_EQ(result.groups[3].first.call, 27u);
}

TEST(TraceDrawState, PolygonAndTransformGroups) {
  const TraceCheckResult result =
      checkLines(kFrustum +
                 "4 glPushAttrib(mask = GL_POLYGON_BIT | GL_TRANSFORM_BIT)\n"
                 "5 glEnable(cap = GL_CULL_FACE)\n6 glCullFace(mode = GL_FRONT)\n"
                 "7 glFrontFace(mode = GL_CW)\n"
                 "8 glClipControl(origin = GL_UPPER_LEFT, depth = GL_ZERO_TO_ONE)\n"
                 "9 glEnable(cap = GL_CLIP_DISTANCE1)\n"
                 "10 glMatrixMode(mode = GL_PROJECTION)\n"
                 "11 glPopAttrib()\n"
                 // Back in GL_MODELVIEW: this scale leaves the projection alone.
                 "12 glScalef(x = 2, y = 2, z = 2)\n"
                 "13 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
                 "14 glPushAttrib(mask = GL_ALL_ATTRIB_BITS)\n"
                 "15 glEnable(cap = GL_CULL_FACE)\n"
                 "16 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
                 "17 glPopAttrib()\n"
                 "18 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n");
  ASSERT_EQ(result.groups.size(), 2u);
  const TraceDepthState& popped = result.groups[0].depth;
  EXPECT_FALSE(popped.cullFace);
  EXPECT_EQ(popped.cullFaceMode, kGlBack);
  EXPECT_EQ(popped.frontFace, kGlCcw);
  EXPECT_FALSE(popped.clipUpperLeft);
  EXPECT_FALSE(popped.clipZeroToOne);
  EXPECT_EQ(popped.clipDistances, 0u);
  EXPECT_EQ(result.groups[0].matrix[0][0], 1.0);  // glFrustum's 2n / (r - l), unscaled
  EXPECT_EQ(result.groups[0].draws, 2u);          // calls 13 and 18
  EXPECT_TRUE(result.groups[1].depth.cullFace);
}

TEST(TraceDrawState, DepthRangeIsClampedAsGlClampsIt) {
  // OpenSCAD's glDepthRange(-100000, 100000): GL holds (0, 1).
  const TraceCheckResult result = checkLines(kFrustum +
                                             "4 glDepthRange(zNear = -100000, zFar = 100000)\n"
                                             "5 glBegin(mode = GL_TRIANGLES)\n6 glEnd()\n"
                                             "7 glDepthRangef(n = 0.25, f = 2)\n"
                                             "8 glBegin(mode = GL_TRIANGLES)\n9 glEnd()\n");
  ASSERT_EQ(result.groups.size(), 2u);
  EXPECT_EQ(result.groups[0].depth.depthRange, glm::dvec2(0.0, 1.0));
  EXPECT_EQ(result.groups[0].depth.depthRangeCall, 4u);
  EXPECT_NE(depthStateLine(result, 0).find("; depth range 0, 1;"), std::string::npos);
  EXPECT_EQ(result.groups[1].depth.depthRange, glm::dvec2(0.25, 1.0));
  EXPECT_NE(depthStateLine(result, 1).find("; depth range 0.25, 1;"), std::string::npos);
}

TEST(TraceDrawState, EqualDepthRangeNamesTheTracedCall) {
  const TraceCheckResult result = checkLines(kFrustum +
                                             "4 glDepthRange(zNear = 1, zFar = 1)\n"
                                             "5 glBegin(mode = GL_TRIANGLES)\n6 glEnd()\n");
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].unusable,
            "glDepthRange(1, 1) at call 4: near and far are equal, so every fragment gets the "
            "same depth");
  EXPECT_EQ(traceCheckText(result).find("--depth-range"), std::string::npos);
  // The matrix check's own refusals name the matrix's source, not its --clip-from-world option:
  // here a glLoadMatrixf whose w is -1 everywhere (an orthographic structure, but GL clips all).
  const TraceCheckResult clippingAll = checkLines(
      "1 glMatrixMode(mode = GL_PROJECTION)\n2 glLoadMatrixf(m = {0.5, 0, 0, 0, 0, 1, "
      "0, 0, 0, 0, -0.2, 0, 0, 0, 0, -1})\n"
      "3 glBegin(mode = GL_TRIANGLES)\n4 glEnd()\n");
  ASSERT_EQ(clippingAll.groups.size(), 1u);
  EXPECT_EQ(clippingAll.groups[0].unusable,
            "fixed-function GL_PROJECTION: row 3 (w) is (0, 0, 0, -1): w <= 0 everywhere, so GL "
            "clips every point");
}

TEST(TraceDrawState, EvaluatorMeshesAreDraws) {
  // osgteapot draws with evaluators only.
  const TraceCheckResult result =
      checkLines(kFrustum +
                 "4 glMapGrid2f(un = 20, u1 = 0, u2 = 1, vn = 20, v1 = 0, v2 = 1)\n"
                 "5 glEvalMesh2(mode = GL_FILL, i1 = 0, i2 = 20, j1 = 0, j2 = 20)\n"
                 "6 glEvalMesh1(mode = GL_LINE, i1 = 0, i2 = 20)\n");
  EXPECT_EQ(result.draws, 2u);
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].first.call, 5u);
  EXPECT_EQ(result.groups[0].first.completedAtCall, 5u);
  EXPECT_EQ(result.groups[0].last.call, 6u);
}

// --verify replays to the call where a draw is complete: eglretrace cannot dump the state between
// glBegin and glEnd.
TEST(TraceDrawState, BeginIsCompletedByItsEnd) {
  const TraceCheckResult result =
      checkLines(kFrustum +
                 "4 glBegin(mode = GL_TRIANGLES)\n5 glVertex3f(x = 0, y = 0, z = -2)\n"
                 "6 glVertex3f(x = 1, y = 0, z = -2)\n7 glVertex3f(x = 0, y = 1, z = -2)\n"
                 "8 glEnd()\n9 glXSwapBuffers(dpy = 0x1, drawable = 0x2)\n"
                 // A glBegin whose glEnd the trace never reached.
                 "10 glBegin(mode = GL_TRIANGLES)\n");
  EXPECT_EQ(result.draws, 2u);
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].first.call, 4u);
  EXPECT_EQ(result.groups[0].first.completedAtCall, 8u);
  EXPECT_EQ(result.groups[0].last.call, 10u);
  EXPECT_EQ(result.groups[0].last.frame, 1u);
  EXPECT_EQ(result.groups[0].last.completedAtCall, 10u);
  // A glBegin left open at a frame's end belongs to that frame.
  const TraceCheckResult open = checkLines(kFrustum +
                                           "4 glBegin(mode = GL_TRIANGLES)\n"
                                           "5 glXSwapBuffers(dpy = 0x1, drawable = 0x2)\n");
  ASSERT_EQ(open.groups.size(), 1u);
  EXPECT_EQ(open.groups[0].first.frame, 0u);
}

// Issue 36's orthographic cases as real programs trace them: OpenSCAD's centred
// glOrtho(..., -D, D) and OpenSceneGraph's pixel HUD (1920 x 1080, near -1, far 1.1), drawn
// classic GL. Both are found (the HUD's size no longer reads as singular) and neither is an error.
TEST(TraceDrawState, CentredAndHudOrthosAreFoundAndNoError) {
  const TraceCheckResult result = checkLines(
      "1 glMatrixMode(mode = GL_PROJECTION)\n"
      "2 glOrtho(left = -41.7, right = 41.7, bottom = -23.3, top = 23.3, zNear = -123.4567, "
      "zFar = 123.4567)\n"
      "3 glBegin(mode = GL_TRIANGLES)\n4 glEnd()\n"
      "5 glLoadIdentity()\n"
      "6 glOrtho(left = 0, right = 1920, bottom = 0, top = 1080, zNear = -1, zFar = 1.1)\n"
      "7 glBegin(mode = GL_QUADS)\n8 glEnd()\n");
  // Two matrices (the HUD one no longer dropped as singular) that read alike: one group.
  EXPECT_EQ(result.distinctPairs, 2u);
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.distinctMatrices, 2u);
  EXPECT_EQ(group.draws, 2u);
  EXPECT_EQ(group.last.call, 7u);
  EXPECT_EQ(group.report.properties.builtFor, "ambiguous");
  EXPECT_EQ(codes(group), std::vector<std::string>{"info:depth-convention-ambiguous"});
  EXPECT_FALSE(result.hasErrors());
}

}  // namespace
}  // namespace clipray::trace

// Multi-pass techniques in `clipray check --trace` (trace/TraceCheck.*): the same matrix drawn in
// one frame under depth tests of both directions, as OpenCSG's CSG passes in
// `openscad --preview` draw it (clear depth to 0 and GL_GREATER to find far surfaces, GL_LESS
// with depth cleared to 1 for the nearest), is a technique, reported per pass as an info; a
// reversed-Z error needs the matrix itself to be reversed. Fed as written dump text.

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "clipray/trace/TraceCheck.hpp"
#include "support/TraceLines.hpp"

namespace clipray::trace {
namespace {

using testing::checkLines;
using testing::codes;

// The lines of the text report from the group's header ("[N] ...") to the next blank line.
std::string groupText(const TraceCheckResult& result, std::size_t group) {
  std::istringstream text(traceCheckText(result));
  std::string line, section;
  const std::string header = "[" + std::to_string(group + 1) + "] ";
  bool inside = false;
  while (std::getline(text, line)) {
    if (line.starts_with(header)) inside = true;
    if (inside && line.empty()) break;
    if (inside) section += line + "\n";
  }
  return section;
}

// Numbered call lines from a list of calls, one per line, starting at call 1.
std::string numbered(const std::string& calls) {
  std::istringstream lines(calls);
  std::string line, text;
  int call = 1;
  while (std::getline(lines, line)) text += std::to_string(call++) + " " + line + "\n";
  return text;
}

const std::string kDraw = "glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n";
const std::string kSwap = "glXSwapBuffers(dpy = 0x1, drawable = 0x2)\n";

// OpenCSG's frame as `openscad --preview` draws it, on GL 2.1's fixed-function stack: the nearest
// surfaces with GL_LESS into depth cleared to 1, the far surfaces of a subtracted volume with
// GL_GREATER into depth cleared to 0, then the nearest again; two frames.
std::string openCsgFrames(const std::string& projection =
                              "glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, "
                              "zNear = 1, zFar = 50)\n") {
  const std::string frame =
      "glClearDepth(depth = 1)\n"
      "glClear(mask = GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT)\n"
      "glDepthFunc(func = GL_LESS)\n" +
      kDraw +
      "glClearDepth(depth = 0)\n"
      "glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
      "glDepthFunc(func = GL_GREATER)\n" +
      kDraw +
      "glClearDepth(depth = 1)\n"
      "glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
      "glDepthFunc(func = GL_LESS)\n" +
      kDraw + kSwap;
  return numbered(
      "glViewport(x = 0, y = 0, width = 64, height = 48)\n"
      "glEnable(cap = GL_DEPTH_TEST)\n"
      "glMatrixMode(mode = GL_PROJECTION)\n" +
      projection + "glMatrixMode(mode = GL_MODELVIEW)\n" + frame + frame);
}

TEST(TraceMultiPass, OpenCsgFarSurfacePassIsAnInfo) {
  const TraceCheckResult result = checkLines(openCsgFrames());
  EXPECT_FALSE(result.hasErrors());
  ASSERT_EQ(result.groups.size(), 2u);
  const TracePairGroup& nearest = result.groups[0];
  EXPECT_EQ(nearest.depth.depthFunc, kGlLess);
  EXPECT_EQ(nearest.draws, 4u);
  EXPECT_TRUE(codes(nearest).empty());
  const TracePairGroup& farthest = result.groups[1];
  EXPECT_EQ(farthest.depth.depthFunc, kGlGreater);
  EXPECT_EQ(farthest.draws, 2u);
  EXPECT_EQ(farthest.report.properties.builtFor, "no");
  EXPECT_FALSE(farthest.report.properties.reversed);
  ASSERT_EQ(codes(farthest), std::vector<std::string>{"info:multi-pass-far-surfaces"});
  EXPECT_EQ(
      farthest.report.findings[0].message,
      "this pass draws with glDepthFunc(GL_GREATER) (call 12) into depth cleared to 0 (call 11), "
      "and frame 0 draws the same matrix with glDepthFunc(GL_LESS) (first at call 9) into "
      "depth cleared to 1: a pass that keeps the farthest surface, the signature of a "
      "multi-pass technique (OpenCSG's CSG passes, depth peeling, shadow volumes), not "
      "reversed-Z; the matrix maps near to the smaller depth, as the GL_LESS pass expects");
  EXPECT_EQ(
      farthest.report.findings[0].fix,
      "nothing, if the technique is intended; picking reads the nearest surface, as the GL_LESS "
      "pass draws it");
  EXPECT_EQ(
      groupText(result, 1),
      "[2] fixed-function GL_PROJECTION: 1 matrix, 2 draws, first frame 0 call 13, last "
      "frame 1 call 26\n"
      "  depth state: clip control lower-left, negative-one-to-one; depth test GL_GREATER; "
      "depth range 0, 1; cleared to 0; viewport 64x48; depth buffer unknown\n"
      "  matrix: perspective, right-handed\n"
      "    eye (0, 0, 0), looking along (0, 0, -1)\n"
      "    near 1, far 50 +-0.00035, fov 73.7398 deg vertical x 90 deg horizontal\n"
      "    built for: no (near 1 if NO, 1.96078 if ZO)\n"
      "      because the NO reading 1 +-2.1e-07 lies within its uncertainty of the round "
      "number 1, the ZO reading 1.96078 +-5.4e-07 lies 0.0392157 from the nearest one, 2\n"
      "    entries read as float32\n"
      "  info [multi-pass-far-surfaces] "
      "this pass draws with glDepthFunc(GL_GREATER) (call 12) into depth cleared to 0 (call 11), "
      "and frame 0 draws the same matrix with glDepthFunc(GL_LESS) (first at call 9) into "
      "depth cleared to 1: a pass that keeps the farthest surface, the signature of a "
      "multi-pass technique (OpenCSG's CSG passes, depth peeling, shadow volumes), not "
      "reversed-Z; the matrix maps near to the smaller depth, as the GL_LESS pass expects"
      "\n"
      "    fix: "
      "nothing, if the technique is intended; picking reads the nearest surface, as the GL_LESS "
      "pass draws it"
      "\n");
  const nlohmann::json json = traceCheckJson(result);
  EXPECT_EQ(json["verdict"], "ok");
  EXPECT_EQ(json["groups"][1]["findings"][0]["code"], "multi-pass-far-surfaces");
  EXPECT_EQ(json["groups"][1]["depth_state"]["depth_func"], "GL_GREATER");
}

TEST(TraceMultiPass, OpenCsgUnderACentredOrthoIsAnInfo) {
  // `openscad --preview --projection=o`: a centred glOrtho(..., -D, D) with a non-round D. An
  // orthographic matrix shows no reversal of its own: the GL_LESS pass says it is classic.
  const TraceCheckResult result = checkLines(
      openCsgFrames("glOrtho(left = -4.8, right = 4.8, bottom = -3.6, top = 3.6, zNear = "
                    "-137.3, zFar = 137.3)\n"));
  EXPECT_FALSE(result.hasErrors());
  ASSERT_EQ(result.groups.size(), 2u);
  EXPECT_FALSE(result.groups[1].report.properties.perspective);
  EXPECT_FALSE(result.groups[1].report.properties.reversed);
  // A centred volume reads alike under NO and ZO (an info of its own); the far-surface pass adds
  // its technique's info and nothing else.
  EXPECT_EQ(codes(result.groups[0]), std::vector<std::string>{"info:depth-convention-ambiguous"});
  EXPECT_EQ(codes(result.groups[1]), (std::vector<std::string>{"info:depth-convention-ambiguous",
                                                               "info:multi-pass-far-surfaces"}));
}

TEST(TraceMultiPass, GreaterWithoutALessPassStaysAnError) {
  // The far-surface pass alone, in a frame of its own: nothing shows a technique, so the test
  // declares reversed-Z and the classic matrix contradicts it.
  const TraceCheckResult result =
      checkLines(numbered("glViewport(x = 0, y = 0, width = 64, height = 48)\n"
                          "glEnable(cap = GL_DEPTH_TEST)\n"
                          "glMatrixMode(mode = GL_PROJECTION)\n"
                          "glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, "
                          "zNear = 1, zFar = 50)\n"
                          "glClearDepth(depth = 1)\n"
                          "glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
                          "glDepthFunc(func = GL_LESS)\n" +
                          kDraw + kSwap +
                          "glClearDepth(depth = 0)\n"
                          "glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
                          "glDepthFunc(func = GL_GREATER)\n" +
                          kDraw + kSwap));
  ASSERT_EQ(result.groups.size(), 2u);
  EXPECT_TRUE(codes(result.groups[0]).empty());
  EXPECT_EQ(codes(result.groups[1]),
            (std::vector<std::string>{"warning:reversed-z-without-zero-to-one",
                                      "error:reversed-z-mismatch", "error:clear-depth-mismatch"}));
}

// OpenCSG's SCS passes as OpenSCAD 2021.01's `--preview` records them (tests/data/trace/real/):
// depth cleared to 0, the farthest front faces with GL_GREATER, then GL_LESS tested against what
// that pass wrote (floriankirsch/OpenCSG, src/renderSCS.cpp), then OpenSCAD's shading with
// GL_EQUAL against the result; two frames. lessFirst: the GL_LESS draw comes before the
// GL_GREATER one in the same clear.
std::string scsFrames(bool lessFirst) {
  const std::string greater = "glDepthFunc(func = GL_GREATER)\n" + kDraw;
  const std::string less =
      "glDepthFunc(func = GL_LESS)\n"
      "glDepthMask(flag = GL_FALSE)\n" +
      kDraw;
  const std::string frame =
      "glClearDepth(depth = 0)\n"
      "glClear(mask = GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT)\n" +
      (lessFirst ? less + greater : greater + less) + "glDepthFunc(func = GL_EQUAL)\n" + kDraw +
      kSwap;
  return numbered(
      "glViewport(x = 0, y = 0, width = 64, height = 48)\n"
      "glEnable(cap = GL_DEPTH_TEST)\n"
      "glMatrixMode(mode = GL_PROJECTION)\n"
      "glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, zNear = 1, zFar = 50)\n"
      "glMatrixMode(mode = GL_MODELVIEW)\n" +
      frame + frame);
}

TEST(TraceMultiPass, LessPassOverTheFarPassIsNotAClearMismatch) {
  // The GL_LESS pass draws into depth cleared to 0, but after the GL_GREATER pass wrote the far
  // surfaces into it: it tests against those (OpenSCAD's preview got six clear-depth errors).
  const TraceCheckResult result = checkLines(scsFrames(false));
  EXPECT_FALSE(result.hasErrors());
  ASSERT_EQ(result.groups.size(), 3u);
  EXPECT_EQ(codes(result.groups[0]), std::vector<std::string>{"info:multi-pass-far-surfaces"});
  const TracePairGroup& over = result.groups[1];
  EXPECT_EQ(over.depth.depthFunc, kGlLess);
  EXPECT_EQ(over.draws, 2u);
  ASSERT_EQ(codes(over), std::vector<std::string>{"info:multi-pass-over-far-surfaces"});
  EXPECT_EQ(over.report.findings[0].message,
            "this pass draws with glDepthFunc(GL_LESS) (call 10) into depth cleared to 0 (call 7) "
            "after frame 0 drew the same matrix into that clear with glDepthFunc(GL_GREATER) "
            "(first at call 9): it tests against the depth that pass wrote, not against the "
            "clear, a step of a multi-pass technique (OpenCSG's CSG passes, depth peeling), not "
            "a clear-depth mismatch");
  EXPECT_EQ(over.report.findings[0].fix, "nothing, if the technique is intended");
  // The GL_EQUAL shading pass tests against that depth too.
  EXPECT_EQ(result.groups[2].depth.depthFunc, kGlEqual);
  EXPECT_EQ(codes(result.groups[2]), std::vector<std::string>{"info:multi-pass-over-far-surfaces"});
  EXPECT_EQ(traceCheckJson(result)["verdict"], "ok");
}

TEST(TraceMultiPass, LessPassBeforeTheFarPassStaysAClearMismatch) {
  // The same passes the other way round: the GL_LESS draw meets the clear value 0 itself, and
  // nothing passes the test.
  const TraceCheckResult result = checkLines(scsFrames(true));
  ASSERT_EQ(result.groups.size(), 3u);
  EXPECT_EQ(result.groups[0].depth.depthFunc, kGlLess);
  EXPECT_EQ(codes(result.groups[0]), std::vector<std::string>{"error:clear-depth-mismatch"});
  EXPECT_EQ(codes(result.groups[1]), std::vector<std::string>{"info:multi-pass-far-surfaces"});
  EXPECT_EQ(codes(result.groups[2]), std::vector<std::string>{"info:multi-pass-over-far-surfaces"});
  EXPECT_TRUE(result.hasErrors());
}

// Reversed-Z, infinite far (near 0.1) under ZERO_TO_ONE: z_clip = 0.1, w_clip = -z_view.
const std::string kReversedMatrix =
    "{1.299038, 0, 0, 0, 0, 1.732051, 0, 0, 0, 0, 0, -1, 0, 0, 0.1, 0}";

TEST(TraceMultiPass, ReversedMatrixWithLessIsStillAnError) {
  // The same reversed matrix drawn with GL_GREATER into depth cleared to 0 (right) and with
  // GL_LESS into depth cleared to 1 in the same frame: the LESS pass keeps the farthest surface
  // of a reversed matrix, and only a reversed matrix can make that an error.
  const TraceCheckResult result = checkLines(
      numbered("glViewport(x = 0, y = 0, width = 64, height = 48)\n"
               "glEnable(cap = GL_DEPTH_TEST)\n"
               "glClipControl(origin = GL_LOWER_LEFT, depth = GL_ZERO_TO_ONE)\n"
               "glUseProgram(program = 1)\n"
               "glGetUniformLocation(program = 1, name = \"clipFromWorld\") = 0\n"
               "glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = " +
               kReversedMatrix +
               ")\n"
               "glClearDepth(depth = 0)\n"
               "glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
               "glDepthFunc(func = GL_GREATER)\n" +
               kDraw +
               "glClearDepth(depth = 1)\n"
               "glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
               "glDepthFunc(func = GL_LESS)\n" +
               kDraw + kSwap));
  ASSERT_EQ(result.groups.size(), 2u);
  EXPECT_EQ(codes(result.groups[0]), std::vector<std::string>{"warning:infinite-far-plane"});
  EXPECT_EQ(codes(result.groups[1]),
            (std::vector<std::string>{"error:reversed-z-mismatch", "warning:infinite-far-plane",
                                      "error:clear-depth-mismatch"}));
  EXPECT_EQ(result.groups[1].report.findings[0].message,
            "the matrix is reversed-Z (near maps to 1, far to 0) but the app declares a classic "
            "depth test: with GL_LESS and clear 1 the farthest surface wins (traced: "
            "glDepthFunc(GL_LESS) at call 13)");
  EXPECT_TRUE(result.hasErrors());
}

}  // namespace
}  // namespace clipray::trace

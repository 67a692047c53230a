// `clipray check --trace` follows GL_POLYGON_OFFSET_FILL and glPolygonOffset(Clamp)(EXT) per draw
// and names an offset that moves depths toward the camera under GL_GREATER: a GL_LESS renderer's
// shadow-caster offset kept through a move to reversed-Z.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "clipray/trace/TraceCheck.hpp"
#include "support/TraceLines.hpp"

namespace clipray::trace {
namespace {

using testing::checkLines;
using testing::codes;

// A classic frustum drawn with the depth test `func` into depth cleared to `clear` (a reversed
// range (1, 0) with GL_GREATER: the nearer surface has the greater depth, as under reversed-Z),
// then `offset` lines and a draw.
std::string offsetDraw(bool greater, const std::string& offset) {
  return std::string(
             "1 glViewport(x = 0, y = 0, width = 64, height = 48)\n"
             "2 glEnable(cap = GL_DEPTH_TEST)\n") +
         (greater ? "3 glDepthFunc(func = GL_GREATER)\n"
                    "4 glDepthRange(zNear = 1, zFar = 0)\n"
                    "5 glClearDepth(depth = 0)\n"
                  : "3 glDepthFunc(func = GL_LESS)\n"
                    "4 glDepthRange(zNear = 0, zFar = 1)\n"
                    "5 glClearDepth(depth = 1)\n") +
         "6 glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
         "7 glMatrixMode(mode = GL_PROJECTION)\n"
         "8 glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, zNear = 1, zFar = 50)\n" +
         offset + "20 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n";
}

const Finding* offsetFinding(const TraceCheckResult& result) {
  if (result.groups.size() != 1) return nullptr;
  for (const Finding& f : result.groups[0].report.findings) {
    if (f.code == "polygon-offset-toward-camera") return &f;
  }
  return nullptr;
}

TEST(TracePolygonOffset, PositiveOffsetUnderGreaterIsAWarningWithTheFlippedSigns) {
  const TraceCheckResult result =
      checkLines(offsetDraw(true,
                            "10 glPolygonOffset(factor = 2, units = 4)\n"
                            "11 glEnable(cap = GL_POLYGON_OFFSET_FILL)\n"));
  ASSERT_EQ(result.groups.size(), 1u);
  // The reversed range of a classic matrix is a finding of its own (depth-range-reversed).
  EXPECT_EQ(codes(result.groups[0]),
            (std::vector<std::string>{"warning:polygon-offset-toward-camera",
                                      "warning:depth-range-reversed"}));
  const Finding* finding = offsetFinding(result);
  ASSERT_NE(finding, nullptr);
  EXPECT_EQ(finding->message,
            "glPolygonOffset(2, 4) (call 10) with GL_POLYGON_OFFSET_FILL enabled (call 11) under "
            "glDepthFunc(GL_GREATER) (call 3): the nearer surface has the greater depth here, so a "
            "positive offset moves the surface toward the camera; kept from a GL_LESS renderer (a "
            "shadow caster's or a hidden-line pass's offset, meant to push away), it pulls the "
            "surface in front of what lies on it: shadow acne and z-fighting return");
  EXPECT_EQ(finding->fix,
            "flip the signs under GL_GREATER: glPolygonOffset(-2, -4) pushes away (a decal meant "
            "to come forward keeps positive values)");
}

TEST(TracePolygonOffset, TheClampVariantsAndTheEnableAreFollowed) {
  // glPolygonOffsetClamp(EXT) set the offset as glPolygonOffset does.
  for (const char* function : {"glPolygonOffsetClamp", "glPolygonOffsetClampEXT"}) {
    const TraceCheckResult clamped =
        checkLines(offsetDraw(true, std::string("10 ") + function +
                                        "(factor = 1, units = 0, clamp = 0.01)\n"
                                        "11 glEnable(cap = GL_POLYGON_OFFSET_FILL)\n"));
    ASSERT_NE(offsetFinding(clamped), nullptr) << function;
    EXPECT_EQ(offsetFinding(clamped)->severity, "warning") << function;
  }
  // Disabled again before the draw: nothing is offset.
  EXPECT_EQ(offsetFinding(checkLines(offsetDraw(true,
                                                "10 glPolygonOffset(factor = 2, units = 4)\n"
                                                "11 glEnable(cap = GL_POLYGON_OFFSET_FILL)\n"
                                                "12 glDisable(cap = GL_POLYGON_OFFSET_FILL)\n"))),
            nullptr);
  // Enabled with GL's default offset (0, 0): nothing moves.
  EXPECT_EQ(
      offsetFinding(checkLines(offsetDraw(true, "11 glEnable(cap = GL_POLYGON_OFFSET_FILL)\n"))),
      nullptr);
  // Pushed away under GL_GREATER (negative), or mixed signs: not named.
  EXPECT_EQ(offsetFinding(checkLines(offsetDraw(true,
                                                "10 glPolygonOffset(factor = -2, units = -4)\n"
                                                "11 glEnable(cap = GL_POLYGON_OFFSET_FILL)\n"))),
            nullptr);
  EXPECT_EQ(offsetFinding(checkLines(offsetDraw(true,
                                                "10 glPolygonOffset(factor = 2, units = -4)\n"
                                                "11 glEnable(cap = GL_POLYGON_OFFSET_FILL)\n"))),
            nullptr);
}

TEST(TracePolygonOffset, OffsetsUnderLessAreNotNamed) {
  // A decal's negative offset comes forward on purpose (so does OSG's ShadowMap's, for the back
  // faces it renders), a shadow caster's positive one pushes away: neither is named.
  for (const char* offset : {"10 glPolygonOffset(factor = -1, units = -2)\n",
                             "10 glPolygonOffset(factor = 1.1, units = 4)\n"}) {
    const TraceCheckResult result = checkLines(
        offsetDraw(false, std::string(offset) + "11 glEnable(cap = GL_POLYGON_OFFSET_FILL)\n"));
    ASSERT_EQ(result.groups.size(), 1u) << offset;
    EXPECT_TRUE(codes(result.groups[0]).empty()) << offset;
  }
}

}  // namespace
}  // namespace clipray::trace

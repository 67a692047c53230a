// What a group of draws reports over all of its matrices (trace/TraceCheck.*, TraceReport.cpp):
// the range of near, far, fov and eye, the draws left out past the per-group cap, and the
// findings a trace gives per draw for clip distances. Fed as written dump text.

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "clipray/trace/TraceCheck.hpp"
#include "support/TraceLines.hpp"

namespace clipray::trace {
namespace {

using testing::checkLines;
using testing::codes;

// The first line of the text report that starts with prefix (after its two-space indent).
std::string reportLine(const TraceCheckResult& result, const std::string& prefix) {
  std::istringstream text(traceCheckText(result));
  std::string line;
  while (std::getline(text, line)) {
    if (line.starts_with("  " + prefix)) return line.substr(2);
  }
  return "(none)";
}

// A fixed-function camera drawn once a frame for `frames` frames: glFrustum(-1, 1, -0.75, 0.75,
// near, far) with near and far scaled by 1, 2, 4 in turn (as OSG computes them per frame), and
// the eye moved back along z by `step` per frame.
std::string movingCamera(int frames, double step, bool scaleDepth) {
  std::ostringstream text;
  text << "1 glViewport(x = 0, y = 0, width = 64, height = 48)\n"
       << "2 glEnable(cap = GL_DEPTH_TEST)\n"
       << "3 glMatrixMode(mode = GL_PROJECTION)\n";
  int call = 4;
  const auto line = [&](const std::string& callText) {
    return std::to_string(call++) + " " + callText + "\n";
  };
  for (int frame = 0; frame < frames; ++frame) {
    const double scale = scaleDepth ? double(1 << (frame % 3)) : 1.0;
    std::ostringstream frustum;
    frustum << "glFrustum(left = " << -scale << ", right = " << scale
            << ", bottom = " << -0.75 * scale << ", top = " << 0.75 * scale << ", zNear = " << scale
            << ", zFar = " << 50 * scale << ")";
    std::ostringstream translate;
    translate << "glTranslatef(x = 0, y = 0, z = " << -step * frame << ")";
    text << line("glLoadIdentity()") << line(frustum.str()) << line(translate.str())
         << line("glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)")
         << line("glXSwapBuffers(dpy = 0x1, drawable = 0x2)");
  }
  return text.str();
}

TEST(TraceGroupRanges, NearFarFovAndEyeOverTheGroup) {
  const TraceCheckResult result = checkLines(movingCamera(3, 0.5, true));
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.distinctMatrices, 3u);
  EXPECT_FALSE(group.leftOut.has_value());
  EXPECT_EQ(reportLine(result, "over its "),
            "over its 3 matrices: near 1 to 4, far 50 to 200, fov 73.7398 deg vertical, eye x 0, "
            "y 0, z 0 to 1 (the lines below read the first)");
  const nlohmann::json json = traceCheckJson(result)["groups"][0];
  // far: 50 and 200 as float32 glFrustum entries give them.
  EXPECT_EQ(json["ranges"].dump(),
            "{\"eye\":{\"max\":[0.0,0.0,1.0],\"min\":[0.0,0.0,0.0]},\"far\":{\"max\":200."
            "00009346012757,\"min\":50.00002336503189},\"fov_y_degrees\":{\"max\":73."
            "73979365244269,\"min\":73.73979365244269},\"near\":{\"max\":4.0,\"min\":1.0}}");
  EXPECT_TRUE(json["left_out"].is_null());
}

TEST(TraceGroupRanges, OneMatrixHasNoRangeLine) {
  const TraceCheckResult result = checkLines(movingCamera(2, 0.0, false));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].distinctMatrices, 1u);
  EXPECT_EQ(reportLine(result, "over its "), "(none)");
  EXPECT_EQ(traceCheckJson(result)["groups"][0]["ranges"].dump(),
            "{\"eye\":{\"max\":[0.0,0.0,0.0],\"min\":[0.0,0.0,0.0]},\"far\":{\"max\":50."
            "00002336503189,\"min\":50.00002336503189},\"fov_y_degrees\":{\"max\":73."
            "73979365244269,\"min\":73.73979365244269},\"near\":{\"max\":1.0,\"min\":1.0}}");
}

// Matrices whose centre of projection is at infinity (a light-space perspective warp, as
// osgshadow --lispsm loads): none has a near, far, fov or eye, so the group's range line says so
// instead of printing an empty list, and the JSON gives no fov, not a zero.
TEST(TraceGroupRanges, EyeAtInfinityHasNothingToRange) {
  std::ostringstream text;
  text << "1 glViewport(x = 0, y = 0, width = 64, height = 48)\n"
       << "2 glEnable(cap = GL_DEPTH_TEST)\n"
       << "3 glMatrixMode(mode = GL_PROJECTION)\n";
  int call = 4;
  for (int frame = 1; frame <= 3; ++frame) {
    // x_clip = frame * x, y_clip = 1, z_clip = y, w_clip = -z (column-major).
    text << call << " glLoadMatrixf(m = {" << frame
         << ", 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 1, 0, 0})\n";
    text << call + 1 << " glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n";
    text << call + 2 << " glXSwapBuffers(dpy = 0x1, drawable = 0x2)\n";
    call += 3;
  }
  const TraceCheckResult result = checkLines(text.str());
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].distinctMatrices, 3u);
  EXPECT_EQ(reportLine(result, "over its "),
            "over its 3 matrices: no near, far, fov or eye to range (the lines below read the "
            "first)");
  EXPECT_EQ(reportLine(result, "  near "), "  near -, far -, fov - (no eye to measure it from)");
  const nlohmann::json json = traceCheckJson(result)["groups"][0];
  EXPECT_EQ(json["ranges"].dump(),
            "{\"eye\":null,\"far\":null,\"fov_y_degrees\":null,\"near\":null}");
  EXPECT_EQ(json["properties"]["eye_at_infinity_along"], nlohmann::json({0.0, 1.0, 0.0}));
  EXPECT_TRUE(json["properties"]["fov_y_degrees"].is_null());
  EXPECT_TRUE(json["properties"]["fov_x_degrees"].is_null());
  EXPECT_TRUE(json["properties"]["fov_error_degrees"].is_null());
}

TEST(TraceGroupRanges, CapIsPerGroupAndSaysWhatItLeftOut) {
  const int frames = static_cast<int>(kMaxPairsPerGroup) + 3;
  const TraceCheckResult result = checkLines(movingCamera(frames, 0.001, false));
  EXPECT_EQ(result.drawsNotKept, 3u);
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.distinctMatrices, kMaxPairsPerGroup);
  ASSERT_TRUE(group.leftOut.has_value());
  EXPECT_EQ(group.leftOut->draws, 3u);
  EXPECT_EQ(group.leftOut->distinctMatrices, 3u);
  EXPECT_EQ(reportLine(result, "left out: "),
            "left out: 3 further draws of this source and depth state (3 more distinct matrices, "
            "frame 1000 call 5007 to frame 1002 call 5017), past the 1000 matrices a group keeps");
  EXPECT_EQ(reportLine(result, "3 draws"),
            "3 draws with further new pairs not analysed (more than 1000 matrices of one source "
            "and depth state, or 20000 pairs in all)");
  EXPECT_EQ(traceCheckJson(result)["groups"][0]["left_out"].dump(),
            "{\"distinct_matrices\":3,\"distinct_matrices_at_least\":false,\"draws\":3,\"first\":{"
            "\"call\":5007,\"frame\":1000},\"last\":{\"call\":5017,\"frame\":1002}}");
}

// A vertex shader that writes gl_ClipDistance[0], drawn by program 1 with its clip plane
// enabled or not.
std::string clippingProgram(const std::string& draws) {
  return "1 glViewport(x = 0, y = 0, width = 64, height = 48)\n"
         "2 glEnable(cap = GL_DEPTH_TEST)\n"
         "3 glCreateShader(type = GL_VERTEX_SHADER) = 5\n"
         "4 glShaderSource(shader = 5, count = 1, string = &\"#version 130\\nvoid main() { "
         "gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; gl_ClipDistance[0] = "
         "gl_Vertex.y; }\", length = NULL)\n"
         "5 glAttachShader(program = 1, shader = 5)\n"
         "6 glLinkProgram(program = 1)\n"
         "7 glUseProgram(program = 1)\n"
         "8 glMatrixMode(mode = GL_PROJECTION)\n"
         "9 glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, zNear = 1, zFar = 50)\n" +
         draws;
}

TEST(TraceGroupRanges, ClipDistanceWrittenButNotEnabled) {
  const TraceCheckResult forgotten =
      checkLines(clippingProgram("10 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"));
  ASSERT_EQ(forgotten.groups.size(), 1u);
  ASSERT_EQ(codes(forgotten.groups[0]),
            std::vector<std::string>{"warning:clip-distance-not-enabled"});
  EXPECT_EQ(forgotten.groups[0].report.findings[0].message,
            "the program writes gl_ClipDistance but no GL_CLIP_DISTANCEi is enabled (none "
            "enabled in the trace): GL ignores the values written (OpenGL 4.6, 13.7), so they "
            "clip nothing");
  EXPECT_EQ(forgotten.groups[0].report.findings[0].fix,
            "glEnable(GL_CLIP_DISTANCE0 + i) before the draw for each gl_ClipDistance[i] the "
            "shader writes");
  // The same program clips in another pass: this one does not clip on purpose.
  const TraceCheckResult reflection =
      checkLines(clippingProgram("10 glEnable(cap = GL_CLIP_DISTANCE0)\n"
                                 "11 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
                                 "12 glDisable(cap = GL_CLIP_DISTANCE0)\n"
                                 "13 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"));
  ASSERT_EQ(reflection.groups.size(), 2u);
  EXPECT_TRUE(codes(reflection.groups[0]).empty());
  ASSERT_EQ(codes(reflection.groups[1]),
            std::vector<std::string>{"info:clip-distance-not-enabled"});
  EXPECT_EQ(reflection.groups[1].report.findings[0].message,
            "the program writes gl_ClipDistance but no GL_CLIP_DISTANCEi is enabled (last "
            "glEnable/glDisable of one at call 12): GL ignores the values written (OpenGL 4.6, "
            "13.7), so they clip nothing; the same program draws with a clip distance enabled "
            "elsewhere (first at call 11): a pass that does not clip on purpose");
  EXPECT_EQ(reflection.groups[1].report.findings[0].fix, "nothing, if this pass should not clip");
}

}  // namespace
}  // namespace clipray::trace

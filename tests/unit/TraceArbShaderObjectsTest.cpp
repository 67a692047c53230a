// ARB_shader_objects programs in `clipray check --trace` (trace/GlTraceState.*,
// trace/UniformBuffers.*): glCreateShaderObjectARB, glShaderSourceARB, glAttachObjectARB,
// glDetachObjectARB, glLinkProgramARB, glUseProgramObjectARB, glGetUniformLocationARB and
// glUniformMatrix4fvARB are followed as their core twins are, with the extension's argument names
// (shaderType, shaderObj, containerObj, obj, attachedObj, programObj). A dump captured from
// tests/traceapps/ConventionApp.cpp's arb-shader-objects case under apitrace 11.1
// (tests/data/trace/arb-shader-objects.dump.txt), and lines written in its form.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/trace/TraceCheck.hpp"
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

std::string refusal(const std::string& text) {
  try {
    checkLines(text);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(accepted)";
}

// Numbered call lines from a list of calls, one per line, starting at call 1.
std::string numbered(const std::string& calls) {
  std::istringstream lines(calls);
  std::string line, text;
  int call = 1;
  while (std::getline(lines, line)) text += std::to_string(call++) + " " + line + "\n";
  return text;
}

// A GL 1.5 app with ARB_shader_objects: glFrustum on the projection stack, program 1 linked from
// shader 2 (a vertex shader of the given source; none: no vertex shader) and shader 3 (fragment),
// then `beforeDraw` and one draw.
std::string arbApp(const std::string& vertexSource, const std::string& beforeDraw = "") {
  std::string calls =
      "glViewport(x = 0, y = 0, width = 64, height = 48)\n"
      "glEnable(cap = GL_DEPTH_TEST)\n"
      "glMatrixMode(mode = GL_PROJECTION)\n"
      "glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, zNear = 1, zFar = 50)\n"
      "glMatrixMode(mode = GL_MODELVIEW)\n"
      "glCreateProgramObjectARB() = 1\n";
  if (!vertexSource.empty()) {
    calls +=
        "glCreateShaderObjectARB(shaderType = GL_VERTEX_SHADER) = 2\n"
        "glShaderSourceARB(shaderObj = 2, count = 1, string = &\"" +
        vertexSource +
        "\", length = NULL)\n"
        "glAttachObjectARB(containerObj = 1, obj = 2)\n";
  }
  calls +=
      "glCreateShaderObjectARB(shaderType = GL_FRAGMENT_SHADER) = 3\n"
      "glShaderSourceARB(shaderObj = 3, count = 1, string = &\"#version 110\\nvoid main() { "
      "gl_FragColor = vec4(1.0); }\\n\", length = NULL)\n"
      "glAttachObjectARB(containerObj = 1, obj = 3)\n"
      "glLinkProgramARB(programObj = 1)\n"
      "glUseProgramObjectARB(programObj = 1)\n" +
      beforeDraw +
      "glBegin(mode = GL_TRIANGLES)\n"
      "glEnd()\n"
      "glXSwapBuffers(dpy = 0x1, drawable = 0x2)\n";
  return numbered(calls);
}

const std::string kFtransform = "#version 110\\nvoid main() { gl_Position = ftransform(); }\\n";

TEST(TraceArbShaderObjects, CapturedUniformCamera) {
  // ConventionApp arb-shader-objects: a NO camera (fov 60, near 0.1, far 100) in a GLSL 1.10
  // uniform, named by glGetUniformLocationARB and set by glUniformMatrix4fvARB.
  const TraceCheckResult result = checkLines(captured("arb-shader-objects.dump.txt"));
  EXPECT_EQ(result.framesSeen, 3u);
  EXPECT_EQ(result.draws, 3u);
  EXPECT_EQ(result.drawsWithProjection, 3u);
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.source, "uniform clipFromWorld (program 1)");
  EXPECT_EQ(group.draws, 3u);
  EXPECT_EQ(group.first.call, 47u);
  EXPECT_EQ(group.first.completedAtCall, 51u);
  EXPECT_EQ(group.report.properties.builtFor, "no");
  ASSERT_TRUE(group.report.properties.near);
  EXPECT_NEAR(group.report.properties.near->value, 0.1, 2e-5);
  EXPECT_NEAR(group.report.properties.fovYDegrees.value, 60.0, 2e-4);
  EXPECT_TRUE(codes(group).empty());
  EXPECT_FALSE(result.hasErrors());
}

TEST(TraceArbShaderObjects, FtransformThroughTheArbEntryPoints) {
  // The shader text comes from glShaderSourceARB, the program's shaders from glAttachObjectARB,
  // their stages from glCreateShaderObjectARB, and glLinkProgramARB links them.
  const TraceCheckResult result = checkLines(arbApp(kFtransform));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source,
            "fixed-function GL_PROJECTION (program 1: its vertex shader calls ftransform())");
  EXPECT_EQ(result.groups[0].report.properties.builtFor, "no");
  EXPECT_TRUE(codes(result.groups[0]).empty());
}

TEST(TraceArbShaderObjects, ProgramWithoutAVertexShaderObject) {
  const TraceCheckResult result = checkLines(arbApp(""));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source,
            "fixed-function GL_PROJECTION (program 1: it has no vertex shader)");
}

TEST(TraceArbShaderObjects, DetachedVertexShaderLeavesTheProgramOnTheStack) {
  // glDetachObjectARB then glLinkProgramARB: what is linked has no vertex shader any more.
  const TraceCheckResult result =
      checkLines(arbApp(kFtransform,
                        "glDetachObjectARB(containerObj = 1, attachedObj = 2)\n"
                        "glLinkProgramARB(programObj = 1)\n"));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source,
            "fixed-function GL_PROJECTION (program 1: it has no vertex shader)");
}

TEST(TraceArbShaderObjects, RelinkResetsTheUniforms) {
  // A camera uniform set, then glLinkProgramARB: the program's uniforms are reset, so the draw
  // has no matrix (its vertex shader reads none of the built-ins either).
  const std::string camera =
      "glGetUniformLocationARB(programObj = 1, name = \"clipFromWorld\") = 0\n"
      "glUniformMatrix4fvARB(location = 0, count = 1, transpose = GL_FALSE, value = {1.299038, "
      "0, 0, 0, 0, 1.608169, -0.3721342, -0.3713907, 0, -0.6432676, -0.9303355, -0.9284767, 0, "
      "0, 5.195746, 5.385165})\n";
  const std::string source =
      "#version 110\\nuniform mat4 clipFromWorld;\\nvoid main() { gl_Position = clipFromWorld "
      "* gl_Vertex; }\\n";
  const TraceCheckResult result = checkLines(arbApp(source, camera));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source, "uniform clipFromWorld (program 1)");
  EXPECT_EQ(refusal(arbApp(source, camera + "glLinkProgramARB(programObj = 1)\n")),
            "app.trace: none of the 1 draws has a matrix with a projection's structure (uniform "
            "mat4, std140 uniform block mat4 or fixed-function GL_PROJECTION)");
}

}  // namespace
}  // namespace clipray::trace

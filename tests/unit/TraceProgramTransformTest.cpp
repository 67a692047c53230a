// Programs that transform through the fixed-function matrix stacks (trace/GlTraceState.*,
// trace/UniformBuffers.*): a GLSL 1.20 vertex shader that calls ftransform() or reads
// gl_ModelViewProjectionMatrix / gl_ProjectionMatrix, or a program without a vertex shader, draws
// with GL_PROJECTION as a draw without a program does (osgtext, osgshadow, osguniformbuffer).
// Found from the traced shader text and glCreateShader's types. Fed as written dump text.

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/trace/Std140Layout.hpp"
#include "clipray/trace/TraceCheck.hpp"
#include "support/TraceLines.hpp"

namespace clipray::trace {
namespace {

using testing::checkLines;
using testing::codes;

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

// A GL 2.1 app: the projection set on the matrix stack (projectionCalls), one program linked
// from a vertex shader (vertexSource, as apitrace escapes it; none: no vertex shader) and a
// fragment shader, one draw.
std::string programApp(const std::string& projectionCalls, const std::string& vertexSource) {
  std::string calls =
      "glViewport(x = 0, y = 0, width = 64, height = 48)\n"
      "glEnable(cap = GL_DEPTH_TEST)\n"
      "glMatrixMode(mode = GL_PROJECTION)\n" +
      projectionCalls +
      "glMatrixMode(mode = GL_MODELVIEW)\n"
      "glTranslatef(x = 0, y = 0, z = -5)\n";
  if (!vertexSource.empty()) {
    calls +=
        "glCreateShader(type = GL_VERTEX_SHADER) = 1\n"
        "glShaderSource(shader = 1, count = 1, string = &\"" +
        vertexSource +
        "\", length = NULL)\n"
        "glAttachShader(program = 3, shader = 1)\n";
  }
  calls +=
      "glCreateShader(type = GL_FRAGMENT_SHADER) = 2\n"
      "glShaderSource(shader = 2, count = 1, string = &\"#version 120\\nvoid main() { "
      "gl_FragColor = vec4(1.0); }\", length = NULL)\n"
      "glAttachShader(program = 3, shader = 2)\n"
      "glLinkProgram(program = 3)\n"
      "glUseProgram(program = 3)\n"
      "glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n"
      "glXSwapBuffers(dpy = 0x1, drawable = 0x2)\n";
  return numbered(calls);
}

const std::string kFrustum =
    "glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, zNear = 1, zFar = 50)\n";
const std::string kFtransform =
    "#version 120\\nuniform vec4 tint;\\nvoid main() { gl_Position = ftransform(); }";

TEST(TraceProgramTransform, FtransformReadsTheProjectionStack) {
  const TraceCheckResult result = checkLines(programApp(kFrustum, kFtransform));
  ASSERT_EQ(result.groups.size(), 1u);
  const TracePairGroup& group = result.groups[0];
  EXPECT_EQ(group.source,
            "fixed-function GL_PROJECTION (program 3: its vertex shader calls ftransform())");
  EXPECT_TRUE(group.report.properties.perspective);
  EXPECT_EQ(group.report.properties.builtFor, "no");
  ASSERT_TRUE(group.report.properties.near && group.report.properties.far);
  EXPECT_NEAR(group.report.properties.near->value, 1.0, 1e-5);
  EXPECT_NEAR(group.report.properties.far->value, 50.0, 1e-2);
  EXPECT_TRUE(codes(group).empty());
  EXPECT_FALSE(result.hasErrors());
}

TEST(TraceProgramTransform, OrthoThroughGlModelViewProjectionMatrix) {
  const TraceCheckResult result = checkLines(programApp(
      "glOrtho(left = -4, right = 4, bottom = -3, top = 3, zNear = 1, zFar = 20)\n",
      "#version 120\\nvoid main() { gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }"));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source,
            "fixed-function GL_PROJECTION (program 3: its vertex shader reads "
            "gl_ModelViewProjectionMatrix)");
  EXPECT_FALSE(result.groups[0].report.properties.perspective);
  EXPECT_TRUE(codes(result.groups[0]).empty());
}

TEST(TraceProgramTransform, ProgramWithoutAVertexShader) {
  const TraceCheckResult result = checkLines(programApp(kFrustum, ""));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].source,
            "fixed-function GL_PROJECTION (program 3: it has no vertex shader)");
}

TEST(TraceProgramTransform, OwnUniformsAndBlocksWithoutAMatrixAreNotBlamed) {
  // A vertex shader with a uniform block of colours (shared layout, no mat4) that transforms
  // with its own vec4 arithmetic, and a projection stack that holds none: refused, and the
  // block, which holds no matrix, is not named as the reason.
  EXPECT_EQ(refusal(programApp("",
                               "#version 140\\nuniform Colors { vec4 tint; };\\nin vec4 "
                               "position;\\nvoid main() { gl_Position = position; }")),
            "app.trace: none of the 1 draws has a matrix with a projection's structure (uniform "
            "mat4, std140 uniform block mat4 or fixed-function GL_PROJECTION)");
  // The same block beside ftransform(): the projection stack is read.
  const TraceCheckResult result = checkLines(
      programApp(kFrustum,
                 "#version 140\\nuniform Colors { vec4 tint; };\\nvoid main() { gl_Position = "
                 "ftransform(); }"));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_TRUE(result.findings.empty());
}

TEST(TraceProgramTransform, BuiltInsReadAsWholeNamesOutsideComments) {
  EXPECT_EQ(fixedFunctionTransformRead("void main() { gl_Position = ftransform(); }"),
            "ftransform()");
  EXPECT_EQ(fixedFunctionTransformRead("gl_Position = gl_ProjectionMatrix * eye;"),
            "gl_ProjectionMatrix");
  EXPECT_EQ(fixedFunctionTransformRead("p = gl_ModelViewProjectionMatrixTranspose * v;"),
            "gl_ModelViewProjectionMatrixTranspose");
  // The first read in the text is named.
  EXPECT_EQ(fixedFunctionTransformRead("a = gl_ProjectionMatrix; b = ftransform();"),
            "gl_ProjectionMatrix");
  EXPECT_EQ(fixedFunctionTransformRead("m = gl_ProjectionMatrixInverse * v;"), "");
  EXPECT_EQ(fixedFunctionTransformRead("// ftransform()\n/* gl_ProjectionMatrix */ x = 1;"), "");
  EXPECT_EQ(fixedFunctionTransformRead("#define T ftransform()\nvoid main() {}"), "");
  EXPECT_EQ(fixedFunctionTransformRead("my_ftransform(); gl_ProjectionMatrix2;"), "");
}

}  // namespace
}  // namespace clipray::trace

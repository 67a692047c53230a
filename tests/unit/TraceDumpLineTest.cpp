// The apitrace dump line parser (harness/clipray/trace/DumpLine.*) on lines as apitrace 11.1
// writes them (`apitrace dump --color=never --multiline=false`).

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/trace/DumpLine.hpp"
#include "clipray/trace/GlTraceState.hpp"

namespace clipray::trace {
namespace {

TEST(TraceDumpLine, HeadOfACallLineWithoutParsingIt) {
  const auto head = dumpCallHead("37 glUniformMatrix4fv(location = 0, count = 1, ...");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->first, 37u);
  EXPECT_EQ(head->second, "glUniformMatrix4fv");
  EXPECT_FALSE(dumpCallHead("// process.name = \"/tmp/app\""));
  EXPECT_FALSE(dumpCallHead("warning: unexpected end of file while reading trace"));
  EXPECT_FALSE(dumpCallHead(""));
}

TEST(TraceDumpLine, MatrixUpload) {
  const DumpCall call = parseDumpCall(
      "48 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = {1.299038, 0, "
      "0, 0, 0, 1.608169, -0.3721342, -0.3713907, 0, -0.6432676, -0.9303355, -0.9284767, 0, 0, "
      "5.195746, 5.385165})");
  EXPECT_EQ(call.number, 48u);
  EXPECT_EQ(call.name, "glUniformMatrix4fv");
  ASSERT_EQ(call.arguments.size(), 4u);
  EXPECT_EQ(call.argument("transpose")->text, "GL_FALSE");
  const DumpValue* value = call.argument("value");
  ASSERT_TRUE(value && value->isList);
  ASSERT_EQ(value->items.size(), 16u);
  EXPECT_EQ(value->items[6].number(), -0.3721342);
  EXPECT_EQ(value->items[15].number(), 5.385165);
  EXPECT_FALSE(call.result);
}

TEST(TraceDumpLine, ResultStringBitmaskAndFlags) {
  const DumpCall location =
      parseDumpCall("28 glGetUniformLocation(program = 1, name = \"clipFromWorld\") = 0");
  EXPECT_TRUE(location.argument("name")->isString);
  EXPECT_EQ(location.argument("name")->text, "clipFromWorld");
  ASSERT_TRUE(location.result);
  EXPECT_EQ(location.result->number(), 0.0);

  const DumpCall clear =
      parseDumpCall("36 glClear(mask = GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT)");
  EXPECT_EQ(clear.argument("mask")->text, "GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT");

  const DumpCall fake =
      parseDumpCall("8 glViewport(x = 0, y = 0, width = 64, height = 48) // fake");
  EXPECT_EQ(fake.argument("height")->number(), 48.0);

  const DumpCall none = parseDumpCall("27 glLoadIdentity()");
  EXPECT_TRUE(none.arguments.empty());
}

TEST(TraceDumpLine, EscapedStringsReferencesBlobsAndStructs) {
  const DumpCall source = parseDumpCall(
      "16 glShaderSource(shader = 2, count = 1, string = &\"#version 450 core\\nuniform mat4 "
      "m; // \\\"x\\\", y)\\n\", length = NULL)");
  EXPECT_EQ(source.argument("string")->text, "#version 450 core\nuniform mat4 m; // \"x\", y)\n");
  EXPECT_EQ(source.argument("length")->text, "NULL");

  const DumpCall buffer = parseDumpCall(
      "33 glBufferData(target = GL_ARRAY_BUFFER, size = 36, data = blob(36), usage = "
      "GL_STATIC_DRAW)");
  EXPECT_EQ(buffer.argument("data")->text, "blob(36)");
  EXPECT_EQ(buffer.argument("usage")->text, "GL_STATIC_DRAW");

  const DumpCall structs =
      parseDumpCall("5 glFoo(rect = {x = 1, y = -2.5}, list = {}, ids = &7) = 0x55deb45c7170");
  ASSERT_EQ(structs.argument("rect")->items.size(), 2u);
  EXPECT_EQ(structs.argument("rect")->items[1].number(), -2.5);
  EXPECT_TRUE(structs.argument("list")->isList);
  EXPECT_TRUE(structs.argument("list")->items.empty());
  EXPECT_EQ(structs.argument("ids")->number(), 7.0);
  EXPECT_EQ(structs.result->number(), 94414997057904.0);  // 0x55deb45c7170
}

TEST(TraceDumpLine, DoublesKeepTheirSixteenDigits) {
  const DumpCall frustum = parseDumpCall(
      "28 glFrustum(left = -0.07698004192353064, right = 0.07698004192353064, bottom = "
      "-0.05773502972201001, top = 0.05773502972201001, zNear = 0.1000000014901161, zFar = 100)");
  EXPECT_EQ(frustum.argument("zNear")->number(), 0.1000000014901161);
  EXPECT_EQ(frustum.argument("left")->number(), -0.07698004192353064);
}

TEST(TraceDumpLine, MalformedLinesNameTheColumn) {
  try {
    parseDumpCall("12 glEnable(cap = GL_DEPTH_TEST");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "column 32: expected ','");
  }
  try {
    parseDumpCall("16 glShaderSource(string = \"never closed)");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "column 42: unterminated string");
  }
}

TEST(TraceDumpLine, EnumsByNameOrNumber) {
  DumpValue value;
  value.text = "GL_GREATER";
  EXPECT_EQ(glEnumValue(value), kGlGreater);
  value.text = "37727";  // 0x935F, written as a number where apitrace's tables lack the name
  EXPECT_EQ(glEnumValue(value), kGlZeroToOne);
  value.text = "GL_SOMETHING_ELSE";
  EXPECT_FALSE(glEnumValue(value));
  EXPECT_EQ(glEnumName(kGlGequal), "GL_GEQUAL");
  EXPECT_EQ(glEnumName(0x1234), "0x1234");
}

TEST(TraceDumpLine, ProjectionStructure) {
  glm::dmat4 perspective(0.0);
  perspective[0][0] = 1.3;
  perspective[1][1] = 1.7;
  perspective[2][2] = -1.002;
  perspective[2][3] = -1.0;
  perspective[3][2] = -0.2;
  EXPECT_TRUE(hasProjectionStructure(perspective));
  glm::dmat4 ortho(1.0);
  ortho[2][2] = -0.02;  // glOrtho flips z
  EXPECT_TRUE(hasProjectionStructure(ortho));
  glm::dmat4 view(1.0);
  view[3] = glm::dvec4(1.0, 2.0, -5.0, 1.0);
  EXPECT_FALSE(hasProjectionStructure(view));
  EXPECT_FALSE(hasProjectionStructure(glm::dmat4(1.0)));
  // glmark2's NormalMatrix: transpose(inverse(modelView)) as uploaded (the modelview translates
  // by (-0.000195, -0.000296, -3.13)): row 3 holds the translation, yet it is no projection.
  EXPECT_FALSE(hasProjectionStructure(glm::transpose(glm::inverse(view))));
  EXPECT_TRUE(hasProjectionStructure(glm::transpose(perspective * view)));
  glm::dmat4 mirror(1.0);
  mirror[1][1] = -1.0;  // a reflected model matrix: orientation reversed, every axis scaled alike
  EXPECT_FALSE(hasProjectionStructure(view * mirror));
  // glOrtho(-1, 1, -1, 1, -1, 1): a cube view volume scales every axis alike too, but on-axis
  // with z alone flipped, glOrtho's shape (so is a model matrix scale(1, 1, -1): read alike).
  glm::dmat4 cube(1.0);
  cube[2][2] = -1.0;
  EXPECT_TRUE(hasProjectionStructure(cube));
  glm::dmat4 offsetCube = cube * 0.1;  // glOrtho(-10, 10, -10, 10, 0, 20)
  offsetCube[3] = glm::dvec4(0.0, 0.0, -1.0, 1.0);
  EXPECT_TRUE(hasProjectionStructure(offsetCube));
  glm::dmat4 xFlipped = cube;
  xFlipped[0][0] = -1.0;  // a point reflection (det < 0): every axis flipped
  xFlipped[1][1] = -1.0;
  EXPECT_FALSE(hasProjectionStructure(xFlipped));
  // A cube volume times a rotating view is no longer on-axis: still missed.
  EXPECT_FALSE(hasProjectionStructure(
      cube * glm::dmat4(glm::dmat3(glm::dvec3(0.6, 0.8, 0.0), glm::dvec3(-0.8, 0.6, 0.0),
                                   glm::dvec3(0.0, 0.0, 1.0)))));
  // A planar shadow projection onto y = 0 from a light at (1, 4, 2): rank 3, no camera.
  const glm::dvec4 light(1.0, 4.0, 2.0, 1.0), plane(0.0, 1.0, 0.0, 0.0);
  glm::dmat4 shadow = glm::dot(plane, light) * glm::dmat4(1.0) - glm::outerProduct(light, plane);
  EXPECT_FALSE(hasProjectionStructure(shadow));
  EXPECT_FALSE(hasProjectionStructure(perspective * view * shadow));
  EXPECT_FALSE(hasProjectionStructure(glm::dmat4(0.0)));
}

// three.js 0.187's makeOrthographic with reversedDepth (c = 1 / (f - n), d = f / (f - n)): z kept,
// orientation kept, so no hasProjectionStructure; its own shape, unequal on-axis scales, is read
// (under a reversed depth test only: GlTraceState). A view, a uniformly scaled or rotated one, is
// not.
TEST(TraceDumpLine, ReversedOrthographicStructure) {
  const double left = -4.0, right = 4.0, top = 3.0, bottom = -3.0, near = 0.1, far = 100.0;
  glm::dmat4 reversed(1.0);
  reversed[0][0] = 2.0 / (right - left);
  reversed[1][1] = 2.0 / (top - bottom);
  reversed[2][2] = 1.0 / (far - near);
  reversed[3][2] = far / (far - near);
  EXPECT_FALSE(hasProjectionStructure(reversed));
  EXPECT_TRUE(hasReversedOrthographicStructure(reversed));
  glm::dmat4 view(1.0);
  view[3] = glm::dvec4(1.0, 2.0, -5.0, 1.0);
  EXPECT_FALSE(hasReversedOrthographicStructure(view));
  EXPECT_FALSE(hasReversedOrthographicStructure(view * 3.0));
  EXPECT_FALSE(hasReversedOrthographicStructure(
      reversed * glm::dmat4(glm::dmat3(glm::dvec3(0.6, 0.8, 0.0), glm::dvec3(-0.8, 0.6, 0.0),
                                       glm::dvec3(0.0, 0.0, 1.0)))));
  glm::dmat4 forward = reversed;
  forward[2][2] = -forward[2][2];  // glOrtho's flipped z: hasProjectionStructure's
  EXPECT_FALSE(hasReversedOrthographicStructure(forward));
  EXPECT_TRUE(hasProjectionStructure(forward));
}

// Singularity by structure, not by the translation's size: a pixel HUD ortho
// gluOrtho2D(0, W, 0, H) (osghud, osgscalarbar) is found at any W * H, as glOrtho and glFrustum
// are at any size: the determinant's sensitivity to the entries' rounding is exactly 4 for them.
TEST(TraceDumpLine, HudOrthoOfAnySizeIsAProjection) {
  for (const double width : {640.0, 1920.0, 4096.0, 16384.0}) {
    const glm::dmat4 hud = glm::orthoRH_NO(0.0, width, 0.0, width * 0.5625, -1.0, 1.0);
    EXPECT_TRUE(hasProjectionStructure(hud)) << width;
    EXPECT_EQ(determinantSensitivity(hud), 4.0) << width;
  }
  EXPECT_EQ(determinantSensitivity(glm::frustumRH_NO(-1.0, 1.0, -0.75, 0.75, 1.0, 50.0)), 4.0);
  EXPECT_EQ(determinantSensitivity(glm::dmat4(0.0)), std::numeric_limits<double>::infinity());
  // A camera 1e4 from the origin with near 0.1: its translation no longer hides it.
  const glm::dmat4 far = glm::perspectiveRH_NO(1.0, 1.5, 0.1, 100.0) *
                         glm::lookAtRH(glm::dvec3(1e4, 2e3, -5e3), glm::dvec3(1e4, 2e3, -5e3 - 1.0),
                                       glm::dvec3(0.0, 1.0, 0.0));
  EXPECT_TRUE(hasProjectionStructure(far));
}

}  // namespace
}  // namespace clipray::trace

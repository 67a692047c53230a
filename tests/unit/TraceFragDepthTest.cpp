// `clipray check --trace` recognises a fragment shader that writes gl_FragDepth (from the traced
// glShaderSource, its preprocessor followed) and says the depth buffer is not projective for the
// draws of that program: three.js's logarithmicDepthBuffer chunk counts only where the program
// defines USE_LOGDEPTHBUF.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "clipray/trace/FragDepthWrite.hpp"
#include "clipray/trace/TraceCheck.hpp"
#include "support/TraceLines.hpp"

namespace clipray::trace {
namespace {

using testing::checkLines;
using testing::codes;

// three.js's logdepthbuf_fragment chunk (mrdoob/three.js
// src/renderers/shaders/ShaderChunk/logdepthbuf_fragment.glsl.js), as apitrace escapes it.
const std::string kLogDepthChunk =
    "#if defined( USE_LOGDEPTHBUF )\\n"
    "  gl_FragDepth = vIsPerspective == 0.0 ? gl_FragCoord.z : log2( vFragDepth ) * "
    "logDepthBufFC * 0.5;\\n"
    "#endif\\n";

// A GL 2.1-style app: a glFrustum projection, program 3 linked from a vertex shader that calls
// ftransform() and the fragment shader `fragmentSource`, one draw with the depth test on.
std::string fragmentApp(const std::string& fragmentSource) {
  return "1 glViewport(x = 0, y = 0, width = 64, height = 48)\n"
         "2 glEnable(cap = GL_DEPTH_TEST)\n"
         "3 glMatrixMode(mode = GL_PROJECTION)\n"
         "4 glFrustum(left = -1, right = 1, bottom = -0.75, top = 0.75, zNear = 1, zFar = 50)\n"
         "5 glCreateShader(type = GL_VERTEX_SHADER) = 1\n"
         "6 glShaderSource(shader = 1, count = 1, string = &\"#version 130\\nvoid main() { "
         "gl_Position = ftransform(); }\", length = NULL)\n"
         "7 glAttachShader(program = 3, shader = 1)\n"
         "8 glCreateShader(type = GL_FRAGMENT_SHADER) = 2\n"
         "9 glShaderSource(shader = 2, count = 1, string = &\"" +
         fragmentSource +
         "\", length = NULL)\n"
         "10 glAttachShader(program = 3, shader = 2)\n"
         "11 glLinkProgram(program = 3)\n"
         "12 glUseProgram(program = 3)\n"
         "13 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n";
}

TEST(TraceFragDepth, ThreeJsLogDepthChunkIsNamedWhereTheProgramDefinesIt) {
  const TraceCheckResult result =
      checkLines(fragmentApp("#version 130\\n#define USE_LOGDEPTHBUF\\nuniform float "
                             "logDepthBufFC;\\nvarying float vFragDepth;\\nvarying float "
                             "vIsPerspective;\\nvoid main() {\\n" +
                             kLogDepthChunk + "}\\n"));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].depth.fragDepthProgram, 3u);
  EXPECT_EQ(codes(result.groups[0]),
            (std::vector<std::string>{"info:fragment-depth-not-projective"}));
  const Finding& finding = result.groups[0].report.findings.at(0);
  EXPECT_EQ(finding.message,
            "program 3 writes gl_FragDepth from its fragment shader: the depth buffer holds the "
            "depth the shader computes (a logarithmic depth of clip w, as three.js's "
            "logarithmicDepthBuffer and Outerra's write), not the projective depth of the matrix, "
            "so the depth buffer is not projective for these draws");
  EXPECT_EQ(finding.fix,
            "depth-buffer picking must invert the same mapping (three.js: w = 2^(d * log2(far + "
            "1)) - 1, then the point at that w along the pixel's ray), not unproject the depth "
            "through the inverse matrix");
  EXPECT_FALSE(result.hasErrors());
}

TEST(TraceFragDepth, TheChunkWithoutItsDefineWritesNothing) {
  const TraceCheckResult result = checkLines(fragmentApp(
      "#version 130\\nvoid main() {\\n" + kLogDepthChunk + "gl_FragColor = vec4(1.0);\\n}\\n"));
  ASSERT_EQ(result.groups.size(), 1u);
  EXPECT_EQ(result.groups[0].depth.fragDepthProgram, 0u);
  EXPECT_TRUE(codes(result.groups[0]).empty());
}

TEST(TraceFragDepth, AssignmentsTheShaderKeeps) {
  EXPECT_TRUE(writesFragDepth("void main() { gl_FragDepth = 0.5; }"));
  EXPECT_TRUE(writesFragDepth("void main() { gl_FragDepth += 0.1; }"));
  EXPECT_TRUE(writesFragDepth("#ifdef LOG\nx\n#else\nvoid main() { gl_FragDepth = 0.5; }\n#endif"));
  EXPECT_TRUE(
      writesFragDepth("#define LOG 1\n#ifndef FLAT\n#if defined(LOG)\n"
                      "void main() { gl_FragDepth=d; }\n#endif\n#endif"));
  // An expression the check does not evaluate counts as kept.
  EXPECT_TRUE(writesFragDepth("#if LOG_LEVEL > 2\ngl_FragDepth = d;\n#endif"));
  // Comments, comparisons, redeclarations and branches the preprocessor drops are no write.
  EXPECT_FALSE(writesFragDepth("// gl_FragDepth = 1.0;\n/* gl_FragDepth = 1.0; */ void main() {}"));
  EXPECT_FALSE(writesFragDepth("layout(depth_greater) out float gl_FragDepth;\nvoid main() {}"));
  EXPECT_FALSE(writesFragDepth("bool b = gl_FragDepth == 0.5;"));
  EXPECT_FALSE(writesFragDepth("#ifdef LOG\ngl_FragDepth = d;\n#endif"));
  EXPECT_FALSE(
      writesFragDepth("#define LOG\n#undef LOG\n#if defined LOG\ngl_FragDepth = d;\n#endif"));
  EXPECT_FALSE(
      writesFragDepth("#if 0\ngl_FragDepth = d;\n#elif !defined(X)\n#else\ngl_FragDepth = "
                      "d;\n#endif"));
}

}  // namespace
}  // namespace clipray::trace

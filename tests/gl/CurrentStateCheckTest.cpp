// engine::checkCurrentState: the depth state of a live context (OSMesa, llvmpipe) read with glGet*,
// declared for the app's matrix. The test sets the state through the context's own loader, as an
// app would with its own GL loader (no GL headers here: the enum values are clipray's).

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "clipray/StateCheck.hpp"
#include "clipray/engine/CurrentStateCheck.hpp"
#include "clipray/trace/GlTraceState.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

constexpr std::uint32_t kGlRenderbuffer = 0x8D41;  // Khronos gl.xml

struct GlCalls {
  explicit GlCalls(gl::GlLoader loader)
      : clipControl(
            reinterpret_cast<void (*)(std::uint32_t, std::uint32_t)>(loader("glClipControl"))),
        depthFunc(reinterpret_cast<void (*)(std::uint32_t)>(loader("glDepthFunc"))),
        enable(reinterpret_cast<void (*)(std::uint32_t)>(loader("glEnable"))),
        frontFace(reinterpret_cast<void (*)(std::uint32_t)>(loader("glFrontFace"))),
        clearDepth(reinterpret_cast<void (*)(double)>(loader("glClearDepth"))),
        viewport(reinterpret_cast<void (*)(int, int, int, int)>(loader("glViewport"))),
        genFramebuffers(
            reinterpret_cast<void (*)(int, std::uint32_t*)>(loader("glGenFramebuffers"))),
        bindFramebuffer(
            reinterpret_cast<void (*)(std::uint32_t, std::uint32_t)>(loader("glBindFramebuffer"))),
        genRenderbuffers(
            reinterpret_cast<void (*)(int, std::uint32_t*)>(loader("glGenRenderbuffers"))),
        bindRenderbuffer(
            reinterpret_cast<void (*)(std::uint32_t, std::uint32_t)>(loader("glBindRenderbuffer"))),
        renderbufferStorage(reinterpret_cast<void (*)(std::uint32_t, std::uint32_t, int, int)>(
            loader("glRenderbufferStorage"))),
        framebufferRenderbuffer(
            reinterpret_cast<void (*)(std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t)>(
                loader("glFramebufferRenderbuffer"))) {}

  // A framebuffer with only a depth renderbuffer of `format`, 64x48.
  void bindDepthFramebuffer(std::uint32_t format) const {
    std::uint32_t framebuffer = 0, renderbuffer = 0;
    genFramebuffers(1, &framebuffer);
    bindFramebuffer(trace::kGlFramebuffer, framebuffer);
    genRenderbuffers(1, &renderbuffer);
    bindRenderbuffer(kGlRenderbuffer, renderbuffer);
    renderbufferStorage(kGlRenderbuffer, format, 64, 48);
    framebufferRenderbuffer(trace::kGlFramebuffer, trace::kGlDepthAttachment, kGlRenderbuffer,
                            renderbuffer);
    viewport(0, 0, 64, 48);
  }

  void (*clipControl)(std::uint32_t, std::uint32_t);
  void (*depthFunc)(std::uint32_t);
  void (*enable)(std::uint32_t);
  void (*frontFace)(std::uint32_t);
  void (*clearDepth)(double);
  void (*viewport)(int, int, int, int);
  void (*genFramebuffers)(int, std::uint32_t*);
  void (*bindFramebuffer)(std::uint32_t, std::uint32_t);
  void (*genRenderbuffers)(int, std::uint32_t*);
  void (*bindRenderbuffer)(std::uint32_t, std::uint32_t);
  void (*renderbufferStorage)(std::uint32_t, std::uint32_t, int, int);
  void (*framebufferRenderbuffer)(std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t);
};

glm::dmat4 columnMajor(const std::vector<double>& values) {
  glm::dmat4 m(0.0);
  for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = values[static_cast<std::size_t>(k)];
  return m;
}

// glm::perspectiveRH_NO(60 deg, 4/3, 0.1, 100) * lookAtRH((0, 2, 5), 0, +Y) in float (7 digits).
const glm::dmat4 kNoMatrix =
    columnMajor({1.299038, 0, 0, 0, 0, 1.608169, -0.3721342, -0.3713907, 0, -0.6432676, -0.9303355,
                 -0.9284767, 0, 0, 5.195746, 5.385165});
// The same camera reversed-Z with an infinite far plane (ZERO_TO_ONE): z_clip = 0.1 w_view.
const glm::dmat4 kReversedMatrix = columnMajor({1.299038, 0, 0, 0, 0, 1.608169, -0, -0.3713907, 0,
                                                -0.6432676, 0, -0.9284767, 0, 0, 0.1, 5.385165});

std::vector<std::string> codes(const CheckReport& report) {
  std::vector<std::string> result;
  for (const Finding& f : report.findings) result.push_back(f.severity + ":" + f.code);
  return result;
}

// A 24-bit depth framebuffer, glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), GL_LESS.
void drawUnderZeroToOneWithLess(const GlCalls& gl) {
  gl.bindDepthFramebuffer(trace::kGlDepthComponent24);
  gl.clipControl(trace::kGlLowerLeft, trace::kGlZeroToOne);
  gl.enable(trace::kGlDepthTest);
  gl.depthFunc(trace::kGlLess);
}

TEST(CurrentStateCheck, NoMatrixUnderZeroToOne) {
  const auto context = testing::createContextForTests();
  drawUnderZeroToOneWithLess(GlCalls(context->loader()));
  const engine::CurrentStateCheck result = engine::checkCurrentState(kNoMatrix, context->loader());
  EXPECT_TRUE(result.state.clipZeroToOne);
  EXPECT_FALSE(result.state.clipUpperLeft);
  EXPECT_TRUE(result.state.depthTest);
  EXPECT_EQ(result.state.depthFunc, trace::kGlLess);
  EXPECT_EQ(result.state.depthFormatName, "24");
  EXPECT_EQ(result.state.viewport, (Viewport{64, 48}));
  EXPECT_EQ(result.state.clearedDepth, 1.0);
  EXPECT_EQ(result.input.declaredDepth, DepthConvention::ZeroToOne);
  EXPECT_EQ(result.report.properties.builtFor, "no");
  EXPECT_EQ(codes(result.report), std::vector<std::string>{"error:depth-convention-mismatch"});
}

TEST(CurrentStateCheck, ReversedZNeedsGreaterAndClearZero) {
  const auto context = testing::createContextForTests();
  const GlCalls gl(context->loader());
  gl.bindDepthFramebuffer(trace::kGlDepthComponent32F);
  gl.clipControl(trace::kGlLowerLeft, trace::kGlZeroToOne);
  gl.enable(trace::kGlDepthTest);
  gl.depthFunc(trace::kGlGreater);
  gl.clearDepth(0.0);
  const engine::CurrentStateCheck right =
      engine::checkCurrentState(kReversedMatrix, context->loader());
  EXPECT_EQ(right.state.depthFormatName, "32f");
  EXPECT_EQ(right.report.properties.builtFor, "zo-reversed");
  EXPECT_EQ(codes(right.report), std::vector<std::string>{"warning:infinite-far-plane"});
  gl.clearDepth(1.0);
  const engine::CurrentStateCheck wrong =
      engine::checkCurrentState(kReversedMatrix, context->loader());
  EXPECT_EQ(codes(wrong.report),
            (std::vector<std::string>{"warning:infinite-far-plane", "error:clear-depth-mismatch"}));
}

// A Direct3D-style app: the projection built y-down for GL_UPPER_LEFT, back faces culled. With
// glFrontFace left at GL_CCW it keeps the insides of its meshes; GL_CW is right.
TEST(CurrentStateCheck, FaceCullingUnderAnUpperLeftOrigin) {
  const auto context = testing::createContextForTests();
  const GlCalls gl(context->loader());
  gl.bindDepthFramebuffer(trace::kGlDepthComponent24);
  gl.clipControl(trace::kGlUpperLeft, trace::kGlNegativeOneToOne);
  gl.enable(trace::kGlDepthTest);
  gl.enable(trace::kGlCullFace);
  glm::dmat4 yDown = kNoMatrix;
  for (int column = 0; column < 4; ++column) yDown[column][1] = -yDown[column][1];
  const engine::CurrentStateCheck wrong = engine::checkCurrentState(yDown, context->loader());
  EXPECT_TRUE(wrong.state.cullFace);
  EXPECT_EQ(wrong.state.cullFaceMode, trace::kGlBack);
  EXPECT_EQ(wrong.state.frontFace, trace::kGlCcw);
  EXPECT_EQ(codes(wrong.report),
            (std::vector<std::string>{"info:y-flipped", "warning:face-culling-keeps-insides"}));
  gl.frontFace(trace::kGlCw);
  const engine::CurrentStateCheck right = engine::checkCurrentState(yDown, context->loader());
  EXPECT_EQ(right.state.frontFace, trace::kGlCw);
  EXPECT_EQ(codes(right.report), std::vector<std::string>{"info:y-flipped"});
  // The same GL_CW with a projection that is not flipped keeps the insides too, but that is an
  // app's choice for meshes wound clockwise: not a finding.
  gl.clipControl(trace::kGlLowerLeft, trace::kGlNegativeOneToOne);
  EXPECT_TRUE(codes(engine::checkCurrentState(kNoMatrix, context->loader()).report).empty());
}

TEST(CurrentStateCheck, DepthClampAndClipDistances) {
  const auto context = testing::createContextForTests();
  const GlCalls gl(context->loader());
  gl.bindDepthFramebuffer(trace::kGlDepthComponent24);
  gl.enable(trace::kGlDepthTest);
  EXPECT_TRUE(codes(engine::checkCurrentState(kNoMatrix, context->loader()).report).empty());
  gl.enable(trace::kGlDepthClamp);
  gl.enable(trace::kGlClipDistance0 + 3);
  const engine::CurrentStateCheck clamped = engine::checkCurrentState(kNoMatrix, context->loader());
  EXPECT_TRUE(clamped.state.depthClamp);
  EXPECT_EQ(clamped.state.clipDistances, 0b1000u);
  ASSERT_EQ(codes(clamped.report), std::vector<std::string>{"info:depth-clamp-near-plane"});
  EXPECT_EQ(clamped.report.findings[0].message,
            "GL_DEPTH_CLAMP is on (glIsEnabled(GL_DEPTH_CLAMP)): nothing is clipped at the near "
            "plane; a surface between the eye and the near plane (0.0999999) is drawn at window "
            "depth 0, the near plane's, so a picking ray that starts on the near plane cannot "
            "hit it and unprojecting the depth buffer there gives a point on the near plane, not "
            "on the surface; likewise a surface beyond the far plane (100) is drawn at window "
            "depth 1, past the end of a ray bounded by it");
}

TEST(CurrentStateCheck, ThePublicEntryPointGivesTheSameFindings) {
  const auto context = testing::createContextForTests();
  drawUnderZeroToOneWithLess(GlCalls(context->loader()));
  const StateCheckResult result = checkCurrentState(kNoMatrix, context->loader());
  ASSERT_EQ(result.findings.size(), 1u);
  EXPECT_EQ(result.findings[0].severity, "error");
  EXPECT_EQ(result.findings[0].code, "depth-convention-mismatch");
  EXPECT_TRUE(result.hasErrors());
  EXPECT_NE(result.text.find("error [depth-convention-mismatch]"), std::string::npos)
      << result.text;
}

}  // namespace
}  // namespace clipray

#include "clipray/engine/CurrentStateCheck.hpp"

#include <algorithm>

#include <glad/gl.h>

#include "clipray/trace/TraceCheck.hpp"

namespace clipray::engine {

namespace {

// The draw framebuffer's depth attachment: its size and component type (GL 4.5 core, 9.2.3).
std::string depthFormatName() {
  GLint framebuffer = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  const GLenum attachment = framebuffer == 0 ? GL_DEPTH : GL_DEPTH_ATTACHMENT;
  GLint objectType = GL_NONE;
  glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, attachment,
                                        GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &objectType);
  if (glGetError() != GL_NO_ERROR || objectType == GL_NONE) return "unknown";
  GLint bits = 0, componentType = GL_NONE;
  glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, attachment,
                                        GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &bits);
  glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, attachment,
                                        GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE, &componentType);
  if (glGetError() != GL_NO_ERROR) return "unknown";
  if (componentType == GL_FLOAT && bits == 32) return "32f";
  if (bits == 16 || bits == 24 || bits == 32) return std::to_string(bits);
  return "unknown";
}

}  // namespace

trace::TraceDepthState readCurrentDepthState(gl::GlLoader loader) {
  const int version = gladLoadGL(loader);
  if (version == 0 || GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 45) {
    throw gl::BackendError("checkCurrentState: no current GL 4.5 context (glClipControl's state)");
  }
  while (glGetError() != GL_NO_ERROR) {
  }
  trace::TraceDepthState state;
  GLint value = 0;
  glGetIntegerv(GL_CLIP_ORIGIN, &value);
  state.clipUpperLeft = value == GL_UPPER_LEFT;
  glGetIntegerv(GL_CLIP_DEPTH_MODE, &value);
  state.clipZeroToOne = value == GL_ZERO_TO_ONE;
  state.depthTest = glIsEnabled(GL_DEPTH_TEST) == GL_TRUE;
  glGetIntegerv(GL_DEPTH_FUNC, &value);
  state.depthFunc = static_cast<std::uint32_t>(value);
  GLdouble range[2] = {0.0, 1.0};
  glGetDoublev(GL_DEPTH_RANGE, range);
  state.depthRange = {range[0], range[1]};
  GLdouble clear = 1.0;
  glGetDoublev(GL_DEPTH_CLEAR_VALUE, &clear);
  state.clearedDepth = clear;  // the value the next depth clear writes
  state.cullFace = glIsEnabled(GL_CULL_FACE) == GL_TRUE;
  glGetIntegerv(GL_CULL_FACE_MODE, &value);
  state.cullFaceMode = static_cast<std::uint32_t>(value);
  glGetIntegerv(GL_FRONT_FACE, &value);
  state.frontFace = static_cast<std::uint32_t>(value);
  state.depthClamp = glIsEnabled(GL_DEPTH_CLAMP) == GL_TRUE;
  // Only the implementation's GL_MAX_CLIP_DISTANCES are enums it takes (at least 8 in GL 3.0 and
  // on): asking for more would leave a GL_INVALID_ENUM for the checks below to find.
  GLint clipDistances = 0;
  glGetIntegerv(GL_MAX_CLIP_DISTANCES, &clipDistances);
  for (int i = 0; i < std::min(clipDistances, trace::kGlClipDistances); ++i) {
    if (glIsEnabled(GL_CLIP_DISTANCE0 + static_cast<GLenum>(i)) == GL_TRUE) {
      state.clipDistances = static_cast<std::uint8_t>(state.clipDistances | (1u << i));
    }
  }
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  state.viewport = {viewport[2], viewport[3]};
  state.depthFormatName = depthFormatName();
  state.depthFormat = parseDepthFormat(state.depthFormatName);
  return state;
}

CurrentStateCheck checkCurrentState(const glm::dmat4& clipFromWorld, gl::GlLoader loader) {
  CurrentStateCheck result;
  result.state = readCurrentDepthState(loader);
  result.report = trace::checkUnderDepthState({"the current GL state", false, clipFromWorld},
                                              result.state, &result.input);
  return result;
}

}  // namespace clipray::engine

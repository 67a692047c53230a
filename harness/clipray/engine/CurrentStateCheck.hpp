#pragma once
// `clipray check` from inside a running app: the depth state of the current GL context, read
// with glGet* (clip control, depth test and func, depth range, clear value, face culling and front
// face, depth clamp and the clip distances enabled, viewport, the draw framebuffer's depth
// format), declared for the matrix the app is about to
// draw with. The same analysis and findings as `clipray check --trace` gives for a draw with this
// state.
//
//   auto result = clipray::engine::checkCurrentState(clipFromWorld, myGetProcAddress);
//   if (result.report.hasErrors()) std::cerr << clipray::checkReportText(result.report,
//   result.input);

#include <glm/glm.hpp>

#include "clipray/check/ConventionCheck.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/trace/GlTraceState.hpp"

namespace clipray::engine {

struct CurrentStateCheck {
  trace::TraceDepthState state;  // as read (call numbers 0; clearedDepth: GL_DEPTH_CLEAR_VALUE)
  CheckInput input;
  CheckReport report;
};

// The GL state read from the current context, with entry points from `loader` (the app's
// eglGetProcAddress, glfwGetProcAddress, ...). Needs GL 4.5 (GL_CLIP_ORIGIN). Throws
// gl::BackendError when no GL 4.5 context is current, InputError when the matrix check refuses the
// matrix.
trace::TraceDepthState readCurrentDepthState(gl::GlLoader loader);

// clipFromWorld: column-major, as uploaded with glUniformMatrix4fv(..., GL_FALSE, ...).
CurrentStateCheck checkCurrentState(const glm::dmat4& clipFromWorld, gl::GlLoader loader);

}  // namespace clipray::engine

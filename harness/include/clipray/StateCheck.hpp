#pragma once
// `clipray check` from inside a running app (a debug build, a test): the depth state of the GL
// context current on the calling thread, read with glGet* (clip origin and depth mode, depth test
// and function, depth range, clear depth, face culling and front face, viewport, the draw
// framebuffer's depth format), checked
// against the matrix the app is about to draw with: the analysis and findings `clipray check
// --trace` gives a traced draw with this state (docs/check.md). Nothing is declared by hand.
//
//   const clipray::StateCheckResult check =
//       clipray::checkCurrentState(clipFromWorld, glfwGetProcAddress);
//   if (check.hasErrors()) std::fprintf(stderr, "%s", check.text.c_str());

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/GlFunctions.hpp"
#include "clipray/InputError.hpp"

namespace clipray {

struct StateFinding {
  std::string severity;  // "error", "warning", "info"
  std::string code;      // "depth-convention-mismatch", "reversed-z-mismatch", ... (docs/check.md)
  std::string message;
  std::string fix;
};

struct StateCheckResult {
  std::vector<StateFinding> findings;
  std::string text;  // the report `clipray check` prints: the matrix's properties, then findings
  bool hasErrors() const;
};

// clipFromWorld: column-major, as the app uploads it with glUniformMatrix4fv(..., GL_FALSE, ...).
// Needs a current GL 4.5 context (GL_CLIP_ORIGIN); throws std::runtime_error without one, and
// InputError for a matrix the check refuses (singular, not finite).
StateCheckResult checkCurrentState(const glm::dmat4& clipFromWorld,
                                   GlGetProcAddress getProcAddress);

}  // namespace clipray

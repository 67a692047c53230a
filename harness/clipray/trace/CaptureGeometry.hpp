#pragma once
// The triangles a captured frame's draws rasterized, as their vertex shaders put them out: the
// capture reader's --geometry lines (RenderDoc's post-VS gl_Position of instance 0, strips and
// fans expanded, indexed draws resolved), for `clipray reconcile --capture`
// (engine/CaptureReconcile.hpp).

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace clipray::trace {

struct CapturedDrawGeometry {
  std::uint64_t event = 0;
  std::string depthTarget;       // the draw framebuffer's depth attachment (RenderDoc's id)
  std::uint64_t instances = 1;   // only instance 0's positions are read
  std::vector<glm::dvec4> clip;  // three clip-space vertices per triangle, in drawing order
  std::string skipped;           // why the draw has no triangles here (lines, no post-VS data)
};

// One --geometry line. Throws std::invalid_argument for a line that is not one (the message says
// what is wrong: missing fields, base64 that does not hold 12 floats per triangle).
CapturedDrawGeometry capturedDrawGeometry(const nlohmann::json& line);

// Whether `clipFromWorld` (a projective matrix among a draw's uniforms) is the one its vertex
// shader computed gl_Position with. A perspective matrix P V M (any affine V M) has a depth row
// that is an affine function of its w row, row_z = A row_w + B (0, 0, 0, 1), so every clip position
// it produces satisfies z = A w + B; another projection's (a light's or a texture's, with other
// near and far planes) A and B do not fit the draw's positions. CannotTell for a matrix without
// that structure (orthographic: w constant; an oblique near plane) or a draw without positions.
enum class ClipFit { Fits, DoesNotFit, CannotTell };
ClipFit fitsClipPositions(const glm::dmat4& clipFromWorld, const std::vector<glm::dvec4>& clip);

}  // namespace clipray::trace

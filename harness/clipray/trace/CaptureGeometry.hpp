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

}  // namespace clipray::trace

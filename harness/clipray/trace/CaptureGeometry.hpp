#pragma once
// The triangles a captured frame's draws rasterized, as their vertex shaders put them out: the
// capture reader's --geometry lines (RenderDoc's post-VS gl_Position of instance 0, strips and
// fans expanded), and each triangle's part inside GL's clip volume in depth, divided into NDC.
// Groundwork for `clipray reconcile --capture` (issue #39): under any projective camera a planar
// triangle stays planar in NDC, and its window depth is affine in window x and y there, so a
// parallel ray through the NDC triangles at a pixel centre meets the depth GL interpolates.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "clipray/Conventions.hpp"

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

using NdcTriangle = std::array<glm::dvec3, 3>;

// The part of clip-space triangle (a, b, c) that GL keeps in depth: z_n w <= z <= w (z_n -1 for
// NEGATIVE_ONE_TO_ONE, 0 for ZERO_TO_ONE; GL 4.6 13.7), which implies w >= 0, clipped in
// homogeneous coordinates (Sutherland-Hodgman, in double) before the division, so that a triangle
// crossing the plane through the eye is not folded through infinity; then divided by w and fanned
// from the first vertex, in the triangle's own winding. x and y are not clipped: what falls outside
// the viewport is never sampled. Empty where nothing of it is kept (or it reaches the eye point).
std::vector<NdcTriangle> ndcTrianglesInDepth(const glm::dvec4& a, const glm::dvec4& b,
                                             const glm::dvec4& c, DepthConvention convention);

}  // namespace clipray::trace

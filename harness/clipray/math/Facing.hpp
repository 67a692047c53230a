#pragma once
// Which triangles face culling leaves drawn, decided as GL decides it.
//
// GL 4.6 14.6.1: a polygon is front-facing when the sign of its area in window coordinates,
// a = 1/2 sum(x_w^i y_w^(i+1) - x_w^(i+1) y_w^i), matches glFrontFace (positive for GL_CCW).
// glClipControl(GL_UPPER_LEFT) negates y_w and also negates a (13.8.1 and the glClipControl
// reference page), so the facing does not depend on the origin: it is the sign of the triangle's
// clip-space orientation det[x; y; w] of the matrix the app draws with. A y-flipped projection or a
// mirrored model matrix changes that sign; the clip origin does not.
//
// For a triangle with every w > 0, det[x; y; w] = w_0 w_1 w_2 * 2a with the viewport's positive
// scales taken out. A triangle that crosses w = 0 keeps the sign on its clipped polygon: every
// vertex of that polygon is a convex combination of the triangle's, in the same order, and has
// w > 0 (Olano and Greer, "Triangle scan conversion using 2D homogeneous coordinates", 1997).

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"

namespace clipray {

// det[x; y; w] of the clip coordinates of a triangle's vertices, in their drawing order: positive
// when the triangle winds counter-clockwise on screen (lower-left origin).
inline double clipOrientation(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c) {
  return a.x * (b.y * c.w - c.y * b.w) - b.x * (a.y * c.w - c.y * a.w) +
         c.x * (a.y * b.w - b.y * a.w);
}

// Whether GL draws a triangle of that orientation under the cull mode and front face. A zero
// orientation (the eye in the triangle's plane) covers no pixel; it counts as back-facing.
inline bool drawnUnderCulling(double orientation, CullFace cull, FrontFace frontFace) {
  if (cull == CullFace::None) return true;
  const bool front = frontFace == FrontFace::Ccw ? orientation > 0.0 : orientation < 0.0;
  return cull == CullFace::Back ? front : !front;
}

}  // namespace clipray

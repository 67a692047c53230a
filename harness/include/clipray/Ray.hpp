#pragma once
// The ray every part of clipray passes around: a world-space origin on the near clip plane, a unit
// direction into the view volume and the parameter range [0, tMax] it is valid for.

#include <glm/glm.hpp>

namespace clipray {

// A camera ray: origin on the near clip plane, unit direction into the frustum,
// t in [0, tMax]; tMax = +inf for an infinite far plane.
struct Ray {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, -1.0};
  double tMax = 0.0;
};

// tMax of a pixel that has no ray (the ray function declined, or the matrix puts that pixel's
// near point behind the eye): a negative tMax never hits anything.
inline constexpr double kNoRayTMax = -1.0;

}  // namespace clipray

#pragma once
// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, as in pbrt-v4 and Embree),
// in double. A ray through a shared edge or vertex of a closed mesh hits at least one of the
// triangles sharing it: edge functions are antisymmetric in the edge's two vertices and are
// computed from per-vertex sheared coordinates, so neighbours agree exactly.

#include <optional>

#include <glm/glm.hpp>

namespace clipray {

// Per-ray precomputation: axis permutation and shear that map the direction to +z.
struct WatertightRay {
  glm::dvec3 origin;
  int kx, ky, kz;
  double shearX, shearY, shearZ;

  WatertightRay(const glm::dvec3& origin, const glm::dvec3& direction);
};

// Ray parameter of the hit in (0, tMax], or nullopt. Degenerate triangles never hit.
std::optional<double> intersectTriangle(const WatertightRay& ray, double tMax, const glm::dvec3& a,
                                        const glm::dvec3& b, const glm::dvec3& c) noexcept;

}  // namespace clipray

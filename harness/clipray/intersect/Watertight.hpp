#pragma once
// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, as in pbrt-v4 and Embree),
// in double. A ray through a shared edge or vertex of a closed mesh hits at least one of the
// triangles sharing it: edge functions are antisymmetric in the edge's two vertices and are
// computed from per-vertex sheared coordinates, so neighbours agree exactly.
//
// The arithmetic below is the definition of a hit: the packet kernels (PacketKernels.cpp) repeat
// it operation for operation, without fused multiply-adds, so their results are bit-identical.

#include <optional>
#include <utility>

#include <glm/glm.hpp>

namespace clipray {

// Per-ray precomputation: axis permutation and shear that map the direction to +z.
struct WatertightRay {
  glm::dvec3 origin;
  int kx, ky, kz;
  double shearX, shearY, shearZ;

  WatertightRay(const glm::dvec3& o, const glm::dvec3& d) : origin(o) {
    const glm::dvec3 absD = glm::abs(d);
    kz = absD.x > absD.y ? (absD.x > absD.z ? 0 : 2) : (absD.y > absD.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    // Keep the winding: swapping kx and ky when d[kz] < 0 keeps edge-function signs meaningful.
    if (d[kz] < 0.0) std::swap(kx, ky);
    shearX = -d[kx] / d[kz];
    shearY = -d[ky] / d[kz];
    shearZ = 1.0 / d[kz];
  }
};

// The exact-on-an-edge case: edge functions recomputed in extended precision (rare; out of line).
void edgeFunctionsExtended(double ax, double ay, double bx, double by, double cx, double cy,
                           double& u, double& v, double& w) noexcept;

// Ray parameter of the hit in (0, tMax], or nullopt. Degenerate triangles never hit. The hit
// depends only on the ray and the triangle: t is computed first, then compared with tMax, so a
// closest-hit search gives the same answer in any visiting order.
inline std::optional<double> intersectTriangle(const WatertightRay& ray, double tMax,
                                               const glm::dvec3& a, const glm::dvec3& b,
                                               const glm::dvec3& c) noexcept {
  const glm::dvec3 A = a - ray.origin;
  const glm::dvec3 B = b - ray.origin;
  const glm::dvec3 C = c - ray.origin;
  const double ax = A[ray.kx] + ray.shearX * A[ray.kz];
  const double ay = A[ray.ky] + ray.shearY * A[ray.kz];
  const double bx = B[ray.kx] + ray.shearX * B[ray.kz];
  const double by = B[ray.ky] + ray.shearY * B[ray.kz];
  const double cx = C[ray.kx] + ray.shearX * C[ray.kz];
  const double cy = C[ray.ky] + ray.shearY * C[ray.kz];

  double u = cx * by - cy * bx;
  double v = ax * cy - ay * cx;
  double w = bx * ay - by * ax;
  // Exactly on an edge in double: decide in extended precision so the sign is exact more often;
  // the computation stays antisymmetric, so neighbours still agree.
  if (u == 0.0 || v == 0.0 || w == 0.0) edgeFunctionsExtended(ax, ay, bx, by, cx, cy, u, v, w);
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return std::nullopt;
  const double det = u + v + w;
  if (det == 0.0) return std::nullopt;

  const double az = ray.shearZ * A[ray.kz];
  const double bz = ray.shearZ * B[ray.kz];
  const double cz = ray.shearZ * C[ray.kz];
  const double tScaled = u * az + v * bz + w * cz;
  const double t = tScaled / det;
  if (!(t > 0.0 && t <= tMax)) return std::nullopt;
  return t;
}

}  // namespace clipray

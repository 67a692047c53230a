#include "clipray/intersect/Watertight.hpp"

#include <cmath>

namespace clipray {

WatertightRay::WatertightRay(const glm::dvec3& o, const glm::dvec3& d) : origin(o) {
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

std::optional<double> intersectTriangle(const WatertightRay& ray, double tMax, const glm::dvec3& a,
                                        const glm::dvec3& b, const glm::dvec3& c) noexcept {
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
  if (u == 0.0 || v == 0.0 || w == 0.0) {
    // Exactly on an edge in double: decide in extended precision so the sign is exact more often;
    // the computation stays antisymmetric, so neighbours still agree.
    const long double lu = static_cast<long double>(cx) * by - static_cast<long double>(cy) * bx;
    const long double lv = static_cast<long double>(ax) * cy - static_cast<long double>(ay) * cx;
    const long double lw = static_cast<long double>(bx) * ay - static_cast<long double>(by) * ax;
    u = static_cast<double>(lu);
    v = static_cast<double>(lv);
    w = static_cast<double>(lw);
  }
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return std::nullopt;
  const double det = u + v + w;
  if (det == 0.0) return std::nullopt;

  const double az = ray.shearZ * A[ray.kz];
  const double bz = ray.shearZ * B[ray.kz];
  const double cz = ray.shearZ * C[ray.kz];
  const double tScaled = u * az + v * bz + w * cz;
  // t = tScaled / det must lie in (0, tMax]; compare without dividing, by the sign of det.
  if (det < 0.0 && (tScaled >= 0.0 || tScaled < tMax * det)) return std::nullopt;
  if (det > 0.0 && (tScaled <= 0.0 || tScaled > tMax * det)) return std::nullopt;
  return tScaled / det;
}

}  // namespace clipray

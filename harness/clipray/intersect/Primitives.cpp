#include "clipray/intersect/Primitives.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace clipray {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Knuth's TwoSum: s + e == a + b exactly (needs strict IEEE evaluation: no -ffast-math).
inline void twoSum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

// t when it is a hit within (0, tMax], else +inf. Written so that NaN never passes.
inline double accept(double t, double tMax) {
  return (t > 0.0 && t <= tMax && t < kInf) ? t : kInf;
}

// Unit sphere x^2 + y^2 + z^2 = 1: a t^2 + 2 b t + c = 0 with a = d.d, b = o.d, c = o.o - 1.
//
// Why not the textbook formula t = (-b -+ sqrt(b^2 - a c)) / a (Ray Tracing Gems, ch. 7,
// "Precision Improvements for Ray/Sphere Intersection"):
// - b^2 - a c cancels catastrophically when the sphere is small seen from afar (b^2 and a c are
//   both ~ |o|^2 |d|^2 while their difference is ~ |d|^2): we use the equal quantity
//   a (1 - |l|^2) with l = o - (b / a) d, the offset from the centre of the ray's closest point,
//   which is small exactly when the difference is;
// - -b + sqrt(disc) cancels for the root whose terms have opposite signs (the near root seen
//   from just above a huge sphere): we only add terms of equal sign, q = -(b + sign(b) sqrt(disc)),
//   and get the other root from the product of the roots, c / a = (q / a)(c / q).
// Each root is then a quotient of quantities with small relative error (a few u each), so each
// root has a relative error of a few u given the local ray; c is computed compensated so that it
// keeps its accuracy when the origin is close to the surface.
double intersectSphere(const glm::dvec3& o, const glm::dvec3& d, double tMax) {
  const double a = glm::dot(d, d);
  if (!(a > 0.0)) return kInf;
  const double b = glm::dot(o, d);
  const glm::dvec3 l = o - (b / a) * d;
  const double disc = a * (1.0 - glm::dot(l, l));
  if (!(disc >= 0.0)) return kInf;  // also NaN
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  // q == 0 only when b == 0 and disc == 0: the origin on the sphere, the ray tangent to it.
  if (q == 0.0) return kInf;
  const double c = lengthSquaredMinusOne(o);
  double t0 = c / q;
  double t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  // The near root when it is ahead; otherwise (origin inside, or on the surface heading in) the
  // far one. A near root beyond tMax means no hit: the far one is further still.
  return accept(t0 > 0.0 ? t0 : t1, tMax);
}

// The plane z = 0; on a hit, x and y of the hit point.
inline double planeT(const glm::dvec3& o, const glm::dvec3& d, double& x, double& y) {
  if (d.z == 0.0) return kInf;  // parallel, including a ray in the plane
  const double t = -o.z / d.z;
  x = o.x + t * d.x;
  y = o.y + t * d.y;
  return t;
}

// Surface of the cube |x|, |y|, |z| <= 1 by the slab test. A zero direction component would make
// (bound - o) / 0 infinite, or NaN when o is on the bound: that slab is instead decided by the
// origin alone (inside it, boundary included, or a miss). Divisions rather than multiplications by
// 1 / d: 0 * inf cannot occur, and the boundary cases (a ray through an edge) are exact.
double intersectBox(const glm::dvec3& o, const glm::dvec3& d, double tMax) {
  double tNear = -kInf;
  double tFar = kInf;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (!(std::abs(o[i]) <= 1.0)) return kInf;
      continue;
    }
    double t0 = (-1.0 - o[i]) / d[i];
    double t1 = (1.0 - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    tNear = std::max(tNear, t0);
    tFar = std::min(tFar, t1);
  }
  if (!(tNear <= tFar)) return kInf;
  // Entering when ahead; otherwise the origin is inside (or on) the box and the exit is the hit.
  return accept(tNear > 0.0 ? tNear : tFar, tMax);
}

}  // namespace

double lengthSquaredMinusOne(const glm::dvec3& v) noexcept {
  // Products split exactly into p + e with fma; sums split exactly with TwoSum; the error terms
  // are summed plainly (they are ~u times the result's inputs, so their rounding is ~u^2).
  double p = v.x * v.x;
  double s = std::fma(v.x, v.x, -p);
  for (int i = 1; i < 3; ++i) {
    const double h = v[i] * v[i];
    const double r = std::fma(v[i], v[i], -h);
    double q = 0.0;
    twoSum(p, h, p, q);
    s += q + r;
  }
  double q = 0.0;
  twoSum(p, -1.0, p, q);
  s += q;
  return p + s;
}

LocalRay toLocal(const AnalyticPrimitive& primitive, const Ray& worldRay) noexcept {
  const glm::dmat3 linear(primitive.localFromWorld);
  const glm::dvec3 position(primitive.worldFromLocal[3]);
  return {linear * (worldRay.origin - position), linear * worldRay.direction};
}

double intersectCanonical(PrimitiveKind kind, const LocalRay& ray, double tMax) noexcept {
  if (!(tMax > 0.0)) return kInf;  // no ray (tMax < 0), an empty range, or NaN
  const glm::dvec3& o = ray.origin;
  const glm::dvec3& d = ray.direction;
  if (!std::isfinite(o.x + o.y + o.z + d.x + d.y + d.z)) return kInf;
  double x = 0.0, y = 0.0;
  switch (kind) {
    case PrimitiveKind::Sphere:
      return intersectSphere(o, d, tMax);
    case PrimitiveKind::Disk: {
      const double t = accept(planeT(o, d, x, y), tMax);
      return t < kInf && x * x + y * y <= 1.0 ? t : kInf;
    }
    case PrimitiveKind::Quad: {
      const double t = accept(planeT(o, d, x, y), tMax);
      return t < kInf && std::abs(x) <= 1.0 && std::abs(y) <= 1.0 ? t : kInf;
    }
    case PrimitiveKind::Box:
      return intersectBox(o, d, tMax);
    case PrimitiveKind::Plane:
      return accept(planeT(o, d, x, y), tMax);
  }
  return kInf;
}

double intersectPrimitive(const AnalyticPrimitive& primitive, const Ray& worldRay) noexcept {
  if (!(worldRay.tMax > 0.0)) return kInf;
  return intersectCanonical(primitive.kind, toLocal(primitive, worldRay), worldRay.tMax);
}

}  // namespace clipray

#pragma once
// Ray intersection of analytic primitives (Scene.hpp: PrimitiveKind), in double, on the CPU.
//
// Each primitive is a canonical shape in its local frame, placed by an affine worldFromLocal.
// The world ray is mapped to the local frame (an affine map keeps the ray parameter t, since
// local(o + t d) = local(o) + t * linear(d)) and intersected with the canonical shape there, so
// the t returned is the world ray's t. Every function here computes the hit's t first and only
// then compares it with tMax: the answer never depends on the bound a closest-hit search passes
// in (SceneIntersector relies on that for its order-independent (t, id) minimum).

#include <glm/glm.hpp>

#include "clipray/Ray.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {

// A ray in a primitive's local frame (direction not normalised: it carries the map's scale).
struct LocalRay {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0};
};

// The world ray in the primitive's local frame: origin = linear(localFromWorld) * (o - p), where
// p is the primitive's world origin (worldFromLocal's translation column), and direction =
// linear(localFromWorld) * d. Mathematically this is localFromWorld * (o, 1); subtracting p first
// makes the rounding proportional to the ray origin's distance from the primitive rather than to
// the size of world coordinates (o_i - p_i is exact when o_i is within a factor two of p_i).
LocalRay toLocal(const AnalyticPrimitive& primitive, const Ray& worldRay) noexcept;

// Closest hit with t in (0, tMax] of a local ray with the canonical shape of `kind`; +inf when
// none (also for tMax <= 0, NaN, a zero direction or non-finite input). Boundaries count as hits
// (disk rim, quad edges and corners, box edges).
double intersectCanonical(PrimitiveKind kind, const LocalRay& ray, double tMax) noexcept;

// Closest hit of a world ray with t in (0, tMax] on the primitive; t = +inf when none.
double intersectPrimitive(const AnalyticPrimitive& primitive, const Ray& worldRay) noexcept;

// |v|^2 - 1 with one final rounding error, up to a term of order u^2 |v|^2 (compensated dot
// product, Ogita-Rump-Oishi "Dot2"). The constant term of the sphere's quadratic: computed
// plainly, it loses all relative accuracy when the origin is close to the sphere (|v| ~ 1).
double lengthSquaredMinusOne(const glm::dvec3& v) noexcept;

}  // namespace clipray

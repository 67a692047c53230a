// The tolerance model for analytic primitives (spheres, disks, quads, boxes, planes), which
// primitive.frag intersects per fragment in float: the depth tolerance of a hit and whether the
// coverage of the primitive may legitimately flip near a pixel.

#include <algorithm>
#include <cmath>

#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/compare/ToleranceTerms.hpp"
#include "clipray/math/Projections.hpp"

namespace clipray {

namespace {

using detail::kFloatUnitRoundoff;
using detail::quantumAt;

// Outward normal of the canonical shape at a local point on it (unnormalized; see Scene.hpp).
glm::dvec3 localNormal(PrimitiveKind kind, const glm::dvec3& p) {
  if (kind == PrimitiveKind::Sphere) return p;
  if (kind == PrimitiveKind::Box) {
    const glm::dvec3 a = glm::abs(p);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    glm::dvec3 n(0.0);
    n[axis] = p[axis] >= 0.0 ? 1.0 : -1.0;
    return n;
  }
  return {0.0, 0.0, 1.0};
}

// Hit state of a ray on one primitive: 0 miss, +1 entering the surface, -1 leaving it (the ray
// starts inside a sphere or box, so the far side is what both sides draw).
int analyticHitState(const SceneIntersector& intersector, std::uint32_t id, const Ray& ray) {
  const Hit hit = intersector.intersectOne(id, ray);
  if (!hit.hit()) return 0;
  const AnalyticPrimitive& primitive = intersector.analyticPrimitive(id);
  const glm::dvec3 origin(primitive.localFromWorld * glm::dvec4(ray.origin, 1.0));
  const glm::dvec3 direction(glm::dmat3(primitive.localFromWorld) * ray.direction);
  const glm::dvec3 p = origin + hit.t * direction;
  const double facing = glm::dot(localNormal(primitive.kind, p), direction);
  if (primitive.kind == PrimitiveKind::Sphere || primitive.kind == PrimitiveKind::Box) {
    return facing <= 0.0 ? 1 : -1;
  }
  return 1;  // flat shapes are seen from either side
}

}  // namespace

double ToleranceModel::analyticDepthTolerance(std::uint32_t primitiveId, const Ray& ray,
                                              double t) const {
  const AnalyticPrimitive& primitive = intersector_.analyticPrimitive(primitiveId);
  const double u = kFloatUnitRoundoff;
  const glm::dmat4& m = setup_.clipFromWorld;
  const glm::dvec3 hitWorld = ray.origin + t * ray.direction;
  const glm::dvec4 c = m * glm::dvec4(hitWorld, 1.0);
  const double zNdc = c.z / c.w;
  const double depth = setup_.windowDepth(zNdc);
  const double toWindow = setup_.windowFromNdcScale();

  // The shader works in the local frame with clipFromLocal rounded to float.
  const AnalyticTransform& transform =
      analyticTransforms_[primitiveId - 1 - intersector_.triangleCount()];
  const glm::dvec3 origin(primitive.localFromWorld * glm::dvec4(ray.origin, 1.0));
  const glm::dvec3 direction(glm::dmat3(primitive.localFromWorld) * ray.direction);
  const glm::dvec3 p = origin + t * direction;

  // 1. Storage: one quantum of the depth format.
  const double storage = quantumAt(setup_.depthFormat, depth);
  // 2. Depth of the hit evaluated in float: z and w are 4-term dot products of float rows with
  //    the float point (6u sum |M_ri p_i|, as for a vertex), then the divide and the mapping (2u).
  double magnitudeZ = 0.0, magnitudeW = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double coordinate = i < 3 ? std::abs(p[i]) : 1.0;
    magnitudeZ += transform.magnitudeRowZ[i] * coordinate;
    magnitudeW += transform.magnitudeRowW[i] * coordinate;
  }
  const double evaluation =
      6.0 * u * (magnitudeZ + std::abs(zNdc) * magnitudeW) / std::abs(c.w) * toWindow +
      2.0 * u * std::abs(depth);
  // 3. Where the float ray meets the surface. The ray (plane crosses, a 3-plane solve) and the
  //    intersection are a few dozen float operations on quantities of size |o| + t|d|: the local
  //    hit point moves by delta = 32 u (|o| + t |d|) across the ray, hence by delta / cos(theta)
  //    along it (theta between ray and normal). Near a tangent the error grows like sqrt(delta)
  //    instead (the shapes have unit size locally), so cos is floored at sqrt(delta).
  const double delta = 32.0 * u * (glm::length(origin) + t * glm::length(direction));
  const glm::dvec3 normal = localNormal(primitive.kind, p);
  const double cosine = std::abs(glm::dot(glm::normalize(normal), glm::normalize(direction)));
  const double alongRay = delta / (glm::length(direction) * std::max(cosine, std::sqrt(delta)));
  // d(window depth)/dt along the world ray: (z' w - z w') / w^2.
  const double zRate = glm::dot(glm::dvec3(matrixRow(m, 2)), ray.direction);
  const double wRate = glm::dot(glm::dvec3(matrixRow(m, 3)), ray.direction);
  const double depthRate = std::abs(zRate * c.w - c.z * wRate) / (c.w * c.w) * toWindow;
  return storage + evaluation + depthRate * alongRay;
}

bool ToleranceModel::analyticEdgeAmbiguous(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  const auto rayAt = [&](glm::dvec2 position) {
    return rays_.generate(
        {2.0 * position.x / viewport_.width - 1.0, 2.0 * position.y / viewport_.height - 1.0});
  };
  const int centre = analyticHitState(intersector_, primitiveId, rayAt(pixel));
  const double e = kAnalyticEdgeEpsilonPixels;
  for (const glm::dvec2 offset :
       {glm::dvec2(e, 0), glm::dvec2(-e, 0), glm::dvec2(0, e), glm::dvec2(0, -e)}) {
    if (analyticHitState(intersector_, primitiveId, rayAt(pixel + offset)) != centre) return true;
  }
  return false;
}

}  // namespace clipray

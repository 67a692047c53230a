// The analytic primitives of a scene file (sphere, disk, quad, box, plane): each becomes the
// canonical shape of Scene.hpp with its worldFromLocal (column-major, p_world = M * p_local).

#include <cmath>
#include <string>
#include <utility>

#include "clipray/math/Projections.hpp"
#include "clipray/scene/SceneReader.hpp"

namespace clipray::detail {

namespace {

// A right-handed orthonormal frame whose z axis is `normal` (Duff et al. 2017, branchless).
glm::dmat4 frameAround(const glm::dvec3& normal) {
  const double sign = std::copysign(1.0, normal.z);
  const double a = -1.0 / (sign + normal.z);
  const double b = normal.x * normal.y * a;
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(1.0 + sign * normal.x * normal.x * a, sign * b, -sign * normal.x, 0.0);
  m[1] = glm::dvec4(b, sign + normal.y * normal.y * a, -normal.y, 0.0);
  m[2] = glm::dvec4(normal, 0.0);
  return m;
}

glm::dmat4 translationScale(const glm::dvec3& translation, const glm::dvec3& scale) {
  glm::dmat4 m(1.0);
  m[0][0] = scale.x;
  m[1][1] = scale.y;
  m[2][2] = scale.z;
  m[3] = glm::dvec4(translation, 1.0);
  return m;
}

}  // namespace

glm::dvec3 SceneReader::direction(const json& value, const Pointer& at) const {
  const glm::dvec3 v = vector3(value, at);
  if (v == glm::dvec3(0.0)) fail(at, "expected a non-zero direction, got " + describe(value));
  return safeNormalize(v);
}

void SceneReader::addPrimitive(PrimitiveKind kind, const glm::dmat4& worldFromLocal,
                               const Pointer& at, std::string primitiveName, Scene& scene) const {
  // Both sides intersect in the primitive's local frame, so the map must be invertible and its
  // inverse finite: the same scaled-determinant test as for matrices given in the file.
  const double scaledDet = scaledDeterminant(glm::dmat3(worldFromLocal));
  if (!allFinite(worldFromLocal) || !(scaledDet >= kSingularThreshold)) {
    fail(at, std::string("the ") + primitiveKindName(kind) +
                 " has a non-invertible placement (scaled determinant " + shortNumber(scaledDet) +
                 "); check \"transform\" / \"worldFromObject\" and the shape's sizes");
  }
  AnalyticPrimitive primitive;
  primitive.name = std::move(primitiveName);
  primitive.kind = kind;
  primitive.worldFromLocal = worldFromLocal;
  primitive.localFromWorld = glm::inverse(worldFromLocal);
  if (!allFinite(primitive.localFromWorld)) {
    fail(at, std::string("the ") + primitiveKindName(kind) +
                 " has a placement whose inverse overflows double");
  }
  scene.primitives.push_back(std::move(primitive));
}

void SceneReader::readSphere(const json& value, const Pointer& at,
                             const glm::dmat4& worldFromObject, std::string sphereName,
                             Scene& scene) const {
  const glm::dvec3 centre = vector3(required(value, at, "centre"), at / "centre");
  const double radius = positiveNumber(required(value, at, "radius"), at / "radius");
  addPrimitive(PrimitiveKind::Sphere,
               worldFromObject * translationScale(centre, glm::dvec3(radius)), at,
               std::move(sphereName), scene);
}

void SceneReader::readDisk(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                           std::string diskName, Scene& scene) const {
  const glm::dvec3 centre = vector3(required(value, at, "centre"), at / "centre");
  const glm::dvec3 normal = direction(required(value, at, "normal"), at / "normal");
  const double radius = positiveNumber(required(value, at, "radius"), at / "radius");
  addPrimitive(PrimitiveKind::Disk,
               worldFromObject * translationScale(centre, glm::dvec3(1.0)) * frameAround(normal) *
                   translationScale(glm::dvec3(0.0), glm::dvec3(radius)),
               at, std::move(diskName), scene);
}

void SceneReader::readQuad(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                           std::string quadName, Scene& scene) const {
  const glm::dvec3 centre = vector3(required(value, at, "centre"), at / "centre");
  const Pointer eAt = at / "halfEdges";
  const json& edges = required(value, at, "halfEdges");
  if (!edges.is_array() || edges.size() != 2) {
    fail(eAt,
         "expected an array of 2 vectors [[ux, uy, uz], [vx, vy, vz]], got " + describe(edges));
  }
  const glm::dvec3 u = vector3(edges[0], eAt / 0), v = vector3(edges[1], eAt / 1);
  // Unit vectors for the test, so that huge (finite) edges cannot overflow it.
  const bool nonZero = u != glm::dvec3(0.0) && v != glm::dvec3(0.0);
  const glm::dvec3 normal =
      nonZero ? glm::cross(safeNormalize(u), safeNormalize(v)) : glm::dvec3(0.0);
  const double scale = std::sqrt(glm::length(u)) * std::sqrt(glm::length(v));
  if (!(glm::length(normal) > kParallelThreshold)) {
    fail(eAt, "expected two non-zero, non-parallel half edges, got " + describe(edges));
  }
  // Local z only has to make the map invertible (the quad is z = 0): the unit normal scaled to
  // the quad's size keeps the map well conditioned.
  glm::dmat4 local(1.0);
  local[0] = glm::dvec4(u, 0.0);
  local[1] = glm::dvec4(v, 0.0);
  local[2] = glm::dvec4(safeNormalize(normal) * scale, 0.0);
  local[3] = glm::dvec4(centre, 1.0);
  addPrimitive(PrimitiveKind::Quad, worldFromObject * local, at, std::move(quadName), scene);
}

void SceneReader::readBox(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                          std::string boxName, Scene& scene) const {
  const json* low = optional(value, "min");
  const json* high = optional(value, "max");
  const json* centreValue = optional(value, "centre");
  const json* extentValue = optional(value, "halfExtents");
  glm::dvec3 centre, halfExtents;
  if ((low || high) && (centreValue || extentValue)) {
    fail(at, "expected either \"min\" and \"max\" or \"centre\" and \"halfExtents\", got both");
  }
  if (low || high) {
    const glm::dvec3 lower = vector3(required(value, at, "min"), at / "min");
    const glm::dvec3 upper = vector3(required(value, at, "max"), at / "max");
    for (int i = 0; i < 3; ++i) {
      if (!(upper[i] > lower[i])) {
        fail(at / "max" / static_cast<std::size_t>(i),
             "expected a number greater than \"min\"[" + std::to_string(i) + "] (" +
                 describe(value["min"][static_cast<std::size_t>(i)]) + "), got " +
                 describe(value["max"][static_cast<std::size_t>(i)]));
      }
    }
    centre = 0.5 * lower + 0.5 * upper;
    halfExtents = 0.5 * upper - 0.5 * lower;
  } else {
    if (!centreValue && !extentValue) {
      fail(at, "missing required fields \"min\" and \"max\" (or \"centre\" and \"halfExtents\")");
    }
    centre = vector3(required(value, at, "centre"), at / "centre");
    const json& extents = required(value, at, "halfExtents");
    halfExtents = vector3(extents, at / "halfExtents");
    for (std::size_t i = 0; i < 3; ++i) {
      if (!(halfExtents[static_cast<int>(i)] > 0.0)) {
        fail(at / "halfExtents" / i, "expected a positive number, got " + describe(extents[i]));
      }
    }
  }
  addPrimitive(PrimitiveKind::Box, worldFromObject * translationScale(centre, halfExtents), at,
               std::move(boxName), scene);
}

void SceneReader::readPlane(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                            std::string planeName, Scene& scene) const {
  const glm::dvec3 point = vector3(required(value, at, "point"), at / "point");
  const glm::dvec3 normal = direction(required(value, at, "normal"), at / "normal");
  addPrimitive(PrimitiveKind::Plane,
               worldFromObject * translationScale(point, glm::dvec3(1.0)) * frameAround(normal), at,
               std::move(planeName), scene);
}

}  // namespace clipray::detail

#include "clipray/intersect/SceneIntersector.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "clipray/intersect/Watertight.hpp"

namespace clipray {

SceneIntersector::SceneIntersector(const Scene& scene, const glm::dvec3& reference)
    : reference_(reference) {
  const PrimitiveIdTable ids(scene);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const MeshObject& object = scene.objects[k];
    for (std::size_t t = 0; t < object.triangles.size(); ++t) {
      const glm::u32vec3 tri = object.triangles[t];
      triangles_.push_back({object.worldPositions[tri.x] - reference,
                            object.worldPositions[tri.y] - reference,
                            object.worldPositions[tri.z] - reference,
                            ids.firstIdOfObject[k] + static_cast<std::uint32_t>(t)});
    }
  }
  if (triangles_.size() > kBvhThreshold) buildBvh();
  slotOfPrimitive_.assign(triangles_.size(), 0);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    slotOfPrimitive_[triangles_[i].primitiveId - 1] = static_cast<std::uint32_t>(i);
  }
}

std::array<glm::dvec3, 3> SceneIntersector::worldTriangle(std::uint32_t primitiveId) const {
  const Triangle& tri = triangles_[slotOfPrimitive_[primitiveId - 1]];
  return {tri.a + reference_, tri.b + reference_, tri.c + reference_};
}

void SceneIntersector::buildBvh() {
  nodes_.reserve(2 * triangles_.size() / 2 + 1);
  buildNode(0, static_cast<std::uint32_t>(triangles_.size()));
}

// Object-median split on the longest centroid axis; leaves of at most 4 triangles.
std::uint32_t SceneIntersector::buildNode(std::uint32_t first, std::uint32_t count) {
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  glm::dvec3 lower(std::numeric_limits<double>::infinity());
  glm::dvec3 upper(-std::numeric_limits<double>::infinity());
  glm::dvec3 centroidLower = lower, centroidUpper = upper;
  for (std::uint32_t i = first; i < first + count; ++i) {
    const Triangle& t = triangles_[i];
    lower = glm::min(glm::min(lower, t.a), glm::min(t.b, t.c));
    upper = glm::max(glm::max(upper, t.a), glm::max(t.b, t.c));
    const glm::dvec3 centroid = (t.a + t.b + t.c) / 3.0;
    centroidLower = glm::min(centroidLower, centroid);
    centroidUpper = glm::max(centroidUpper, centroid);
  }
  nodes_[index].lower = lower;
  nodes_[index].upper = upper;
  if (count <= 4) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  const glm::dvec3 extent = centroidUpper - centroidLower;
  const int axis =
      extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
  const std::uint32_t half = count / 2;
  std::nth_element(triangles_.begin() + first, triangles_.begin() + first + half,
                   triangles_.begin() + first + count,
                   [axis](const Triangle& l, const Triangle& r) {
                     return l.a[axis] + l.b[axis] + l.c[axis] < r.a[axis] + r.b[axis] + r.c[axis];
                   });
  buildNode(first, half);
  const std::uint32_t second = buildNode(first + half, count - half);
  nodes_[index].first = second;
  nodes_[index].count = 0;
  return index;
}

namespace {
// Keeps the closest hit; an equal t goes to the smaller primitive id, so the answer does not
// depend on the order triangles are visited in.
template <typename Triangle>
void testTriangle(const WatertightRay& ray, const Triangle& tri, Hit& best) {
  const auto t = intersectTriangle(ray, best.t, tri.a, tri.b, tri.c);
  if (!t) return;
  if (*t < best.t || best.primitiveId == 0 || tri.primitiveId < best.primitiveId) {
    best.t = *t;
    best.primitiveId = tri.primitiveId;
  }
}
}  // namespace

Hit SceneIntersector::closestHitLinear(const Ray& worldRay) const noexcept {
  const double sum = worldRay.origin.x + worldRay.origin.y + worldRay.origin.z +
                     worldRay.direction.x + worldRay.direction.y + worldRay.direction.z;
  if (!std::isfinite(sum)) return Hit{};
  const WatertightRay ray(worldRay.origin - reference_, worldRay.direction);
  Hit best;
  best.t = worldRay.tMax;
  for (const Triangle& tri : triangles_) testTriangle(ray, tri, best);
  if (best.primitiveId == 0) best.t = std::numeric_limits<double>::infinity();
  return best;
}

Hit SceneIntersector::closestHit(const Ray& worldRay) const noexcept {
  // A ray function may hand us a non-finite ray (e.g. a near point unprojected at infinity):
  // it hits nothing, rather than producing a NaN "hit" from comparisons that are all false.
  const double sum = worldRay.origin.x + worldRay.origin.y + worldRay.origin.z +
                     worldRay.direction.x + worldRay.direction.y + worldRay.direction.z;
  if (!std::isfinite(sum)) return Hit{};
  const glm::dvec3 origin = worldRay.origin - reference_;
  const WatertightRay ray(origin, worldRay.direction);
  Hit best;
  best.t = worldRay.tMax;
  auto visit = [&](const Triangle& tri) { testTriangle(ray, tri, best); };
  if (nodes_.empty()) {
    for (const Triangle& tri : triangles_) visit(tri);
  } else {
    const glm::dvec3 inverseDirection = 1.0 / worldRay.direction;
    // Ize's robust slab test: widen the far distance by 2 gamma(3) so rounding never culls a box
    // the ray grazes.
    constexpr double kEps = std::numeric_limits<double>::epsilon() * 0.5;
    constexpr double kWiden = 1.0 + 2.0 * (3.0 * kEps) / (1.0 - 3.0 * kEps);
    auto slab = [&](const Node& node, double& entry) {
      double tNear = 0.0, tFar = best.t;
      for (int k = 0; k < 3; ++k) {
        double t0 = (node.lower[k] - origin[k]) * inverseDirection[k];
        double t1 = (node.upper[k] - origin[k]) * inverseDirection[k];
        if (t0 > t1) std::swap(t0, t1);
        if (std::isnan(t0) || std::isnan(t1))
          continue;  // 0 * inf: origin on the slab, direction parallel
        t1 *= kWiden;
        tNear = t0 > tNear ? t0 : tNear;
        tFar = t1 < tFar ? t1 : tFar;
        if (tNear > tFar) return false;
      }
      entry = tNear;
      return true;
    };
    std::uint32_t stack[64];
    int top = 0;
    double entry = 0.0;
    if (slab(nodes_[0], entry)) stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) visit(triangles_[i]);
        continue;
      }
      const std::uint32_t left = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
      const std::uint32_t right = node.first;
      double entryLeft = 0.0, entryRight = 0.0;
      const bool hitLeft = slab(nodes_[left], entryLeft);
      const bool hitRight = slab(nodes_[right], entryRight);
      // Visit the nearer child first (pushed last); ties keep a fixed order.
      if (hitLeft && hitRight) {
        if (entryLeft <= entryRight) {
          stack[top++] = right;
          stack[top++] = left;
        } else {
          stack[top++] = left;
          stack[top++] = right;
        }
      } else if (hitLeft) {
        stack[top++] = left;
      } else if (hitRight) {
        stack[top++] = right;
      }
    }
  }
  if (best.primitiveId == 0) best.t = std::numeric_limits<double>::infinity();
  return best;
}

}  // namespace clipray

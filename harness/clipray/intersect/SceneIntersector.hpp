#pragma once
// Closest-hit queries against every triangle of a scene, in double and camera-relative: vertices
// are stored relative to a reference point (near the camera) so that ray origins and vertices
// carry small coordinates. A BVH is built only when the triangle count makes it pay.

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/rays/Ray.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {

struct Hit {
  double t = std::numeric_limits<double>::infinity();
  std::uint32_t primitiveId = 0;  // 0: no hit (see PrimitiveIdTable)
  bool hit() const { return primitiveId != 0; }
};

class SceneIntersector {
 public:
  // Below this many triangles a linear scan is faster than building and walking a BVH.
  static constexpr std::size_t kBvhThreshold = 64;

  SceneIntersector(const Scene& scene, const glm::dvec3& reference);

  // Closest hit with t in (0, ray.tMax]; ties go to the smaller primitive id. Never throws.
  Hit closestHit(const Ray& worldRay) const noexcept;
  // The same query by a linear scan of every triangle (the reference the BVH must match exactly).
  Hit closestHitLinear(const Ray& worldRay) const noexcept;

  // World-space vertices of a primitive (id from PrimitiveIdTable); id must be valid.
  std::array<glm::dvec3, 3> worldTriangle(std::uint32_t primitiveId) const;
  std::size_t triangleCount() const { return triangles_.size(); }
  bool usesBvh() const { return !nodes_.empty(); }
  const glm::dvec3& reference() const { return reference_; }

 private:
  struct Triangle {
    glm::dvec3 a, b, c;  // relative to reference_
    std::uint32_t primitiveId;
  };
  struct Node {
    glm::dvec3 lower, upper;
    std::uint32_t first;  // leaf: first triangle; inner: index of the second child
    std::uint32_t count;  // leaf: triangle count (> 0); inner: 0
  };
  void buildBvh();
  std::uint32_t buildNode(std::uint32_t first, std::uint32_t count);

  glm::dvec3 reference_;
  std::vector<Triangle> triangles_;             // in BVH leaf order when a BVH is built
  std::vector<std::uint32_t> slotOfPrimitive_;  // primitiveId - 1 -> index in triangles_
  std::vector<Node> nodes_;
};

}  // namespace clipray

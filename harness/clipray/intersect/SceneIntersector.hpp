#pragma once
// Closest-hit queries against every triangle of a scene, in double and camera-relative: vertices
// are stored relative to a reference point (near the camera) so that ray origins and vertices
// carry small coordinates. A BVH (binned SAH, double bounds) is built only when the triangle
// count makes it pay. Every query answers exactly what closestHitLinear answers: the smallest
// (t, primitive id) over all triangles, with each triangle's t computed by the same watertight
// arithmetic; BVH culling is conservative (padded boxes, widened ranges), never decisive.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
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

namespace detail {
struct PacketKernels;
// Storage layout of SceneIntersector (internal; shared with the packet kernels).
struct BvhTriangle {
  glm::dvec3 a, b, c;  // relative to the reference point
  std::uint32_t primitiveId;
};
struct BvhNode {
  // Padded outwards (see SceneIntersector's constructor) and rounded outwards to float: culling
  // only needs conservative boxes, and 32-byte nodes halve the memory traffic of a walk.
  float lower[3], upper[3];
  std::uint32_t first;  // leaf: first triangle; inner: index of the second child
  std::uint16_t count;  // leaf: triangle count (> 0); inner: 0
  std::uint16_t axis;   // inner: split axis; the first child holds the smaller centroids
};
}  // namespace detail

class SceneIntersector {
 public:
  // Below this many triangles a linear scan is faster than building and walking a BVH.
  static constexpr std::size_t kBvhThreshold = 64;
  // Rays traced together by closestHits (a tile of 8x8 primary rays).
  static constexpr std::size_t kMaxPacket = 64;

  SceneIntersector(const Scene& scene, const glm::dvec3& reference);

  // Closest hit with t in (0, ray.tMax]; ties go to the smaller primitive id. Never throws.
  Hit closestHit(const Ray& worldRay) const noexcept;
  // The same query by a linear scan of every triangle (the reference the BVH must match exactly).
  Hit closestHitLinear(const Ray& worldRay) const noexcept;
  // closestHit for many rays at once: hits[i] is bit-identical to closestHit(rays[i]). Fastest
  // for coherent rays (a tile of neighbouring primary rays): traced as SIMD packets of up to
  // kMaxPacket rays sharing one BVH walk. hits.size() must equal rays.size(). Never throws.
  void closestHits(std::span<const Ray> rays, std::span<Hit> hits) const noexcept;
  // The same for a tile of a row-major frame: rays and hits point at the tile's first pixel,
  // rows are rowStride elements apart; width * height <= kMaxPacket rays are traced together.
  void closestHitsTile(const Ray* rays, Hit* hits, std::size_t rowStride, int width,
                       int height) const noexcept;

  // World-space vertices of a primitive (id from PrimitiveIdTable); id must be valid.
  std::array<glm::dvec3, 3> worldTriangle(std::uint32_t primitiveId) const;
  std::size_t triangleCount() const { return triangles_.size(); }
  bool usesBvh() const { return !nodes_.empty(); }
  const glm::dvec3& reference() const { return reference_; }
  std::size_t nodeCount() const { return nodes_.size(); }
  // Bytes held by the triangle copies, the BVH and the id map.
  std::size_t memoryBytes() const;
  // Whether closestHits runs the AVX2 packet kernels on this CPU (else one ray at a time).
  static bool packetKernelsAvailable();

 private:
  friend struct detail::PacketKernels;
  using Triangle = detail::BvhTriangle;
  using Node = detail::BvhNode;
  void buildBvh();

  glm::dvec3 reference_;
  double boxPad_ = 0.0;
  std::vector<Triangle> triangles_;             // in BVH leaf order when a BVH is built
  std::vector<std::uint32_t> slotOfPrimitive_;  // primitiveId - 1 -> index in triangles_
  std::vector<Node> nodes_;                     // depth-first: the first child follows its parent
};

}  // namespace clipray

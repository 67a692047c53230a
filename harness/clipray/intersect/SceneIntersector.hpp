#pragma once
// Closest-hit queries against every primitive of a scene, in double: triangles and analytic
// primitives (spheres, disks, quads, boxes, planes; Primitives.hpp).
// Triangles are stored camera-relative: vertices are relative to a reference point (near the
// camera) so that ray origins and vertices carry small coordinates. A BVH over the triangles
// (binned SAH, double bounds) is built only when the triangle count makes it pay; analytic
// primitives are few and are tested one after the other. Every query answers exactly what
// closestHitLinear answers: the smallest (t, primitive id) over all primitives, with each
// primitive's t computed by the same arithmetic (watertight for triangles); BVH culling is
// conservative (padded boxes, widened ranges), never decisive.
// With the matrix a frame is drawn with, the triangles its objects' face culling removes
// (math/Facing.hpp) are left out of every query, as the rasterizer leaves them out of the picture.

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Ray.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {

class FrameBins;

struct Hit {
  double t = std::numeric_limits<double>::infinity();
  std::uint32_t primitiveId = 0;  // 0: no hit (see PrimitiveIdTable)
  bool hit() const { return primitiveId != 0; }
};

namespace detail {
struct PacketKernels;
struct ScreenTriangles;
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

  // When the BVH is built: now (the constructor), or by the first query that walks it (a frame of
  // camera rays traced from screen-space bins never does; the build is thread-safe).
  enum class BvhBuild { Now, WhenFirstNeeded };

  // drawnClipFromWorld: the matrix the frame is drawn with (column-major, p_clip = M * p_world, as
  // GL gets it, any clip origin), which decides the facing of each triangle of a culling object;
  // nullopt: no triangle is culled.
  SceneIntersector(const Scene& scene, const glm::dvec3& reference,
                   BvhBuild bvhBuild = BvhBuild::Now,
                   const std::optional<glm::dmat4>& drawnClipFromWorld = std::nullopt);

  // Closest hit with t in (0, ray.tMax]; ties go to the smaller primitive id. Never throws.
  Hit closestHit(const Ray& worldRay) const noexcept;
  // The same query by a linear scan of every primitive (the reference the BVH must match exactly).
  Hit closestHitLinear(const Ray& worldRay) const noexcept;
  // closestHit for many rays at once: hits[i] is bit-identical to closestHit(rays[i]). Fastest
  // for coherent rays (a tile of neighbouring primary rays): traced as SIMD packets of up to
  // kMaxPacket rays sharing one BVH walk. hits.size() must equal rays.size(). Never throws.
  void closestHits(std::span<const Ray> rays, std::span<Hit> hits) const noexcept;
  // The same for a tile of a row-major frame: rays and hits point at the tile's first pixel,
  // rows are rowStride elements apart; width * height <= kMaxPacket rays are traced together.
  void closestHitsTile(const Ray* rays, Hit* hits, std::size_t rowStride, int width,
                       int height) const noexcept;
  // closestHitsTile for tile (tileX, tileY) of the frame that `bins` were made for (8x8 tiles,
  // FrameBins::kTile): the same hits, bit for bit; packets whose rays stay on their pixel
  // centres' lines of sight test the tile's binned triangles instead of walking the BVH. Returns
  // whether every packet of the tile did.
  bool closestHitsTileBinned(const FrameBins& bins, int tileX, int tileY, const Ray* rays,
                             Hit* hits, std::size_t rowStride, int width,
                             int height) const noexcept;

  // Closest hit of the ray with the one primitive `primitiveId` (a triangle or an analytic
  // primitive), t in (0, ray.tMax]: the t that closestHit would see for that primitive, bit for
  // bit. Hit{} when it misses, the triangle is culled or the id is not a valid primitive id.
  // Never throws.
  Hit intersectOne(std::uint32_t primitiveId, const Ray& worldRay) const noexcept;

  // World-space vertices of a triangle (id from PrimitiveIdTable); id must be a triangle's.
  std::array<glm::dvec3, 3> worldTriangle(std::uint32_t primitiveId) const;
  // The scene's triangles, culled ones included (analytic primitives are counted by
  // analyticCount).
  std::size_t triangleCount() const { return triangleIdCount_; }
  // Triangles that face culling leaves out of every query.
  std::size_t culledCount() const { return triangleIdCount_ - triangles_.size(); }
  // Whether the triangle with that id is culled; false for any other id.
  bool culled(std::uint32_t primitiveId) const {
    return !culled_.empty() && primitiveId >= 1 && primitiveId <= triangleIdCount_ &&
           culled_[primitiveId - 1] != 0;
  }
  std::size_t analyticCount() const { return primitives_.size(); }
  // Valid primitive ids are 1..primitiveIdCount(): triangles first, then analytic primitives.
  std::uint32_t primitiveIdCount() const {
    return static_cast<std::uint32_t>(triangleIdCount_ + primitives_.size());
  }
  bool isAnalytic(std::uint32_t primitiveId) const {
    return primitiveId >= firstAnalyticId_ && primitiveId - firstAnalyticId_ < primitives_.size();
  }
  // The analytic primitive with that id; isAnalytic(primitiveId) must hold.
  const AnalyticPrimitive& analyticPrimitive(std::uint32_t primitiveId) const {
    return primitives_[primitiveId - firstAnalyticId_];
  }
  // Whether queries walk a BVH (built now or when first needed): the triangle count makes it pay.
  bool usesBvh() const { return wantsBvh_; }
  // Whether the BVH has been built (BvhBuild::WhenFirstNeeded builds it on demand).
  bool bvhBuilt() const { return bvh_->built.load(std::memory_order_acquire); }
  const glm::dvec3& reference() const { return reference_; }
  std::size_t nodeCount() const { return bvhBuilt() ? bvh_->nodes.size() : 0; }
  // Bytes held by the triangle copies, the BVH, the id map and the analytic primitives.
  std::size_t memoryBytes() const;
  // Whether closestHits runs the AVX2 packet kernels on this CPU (else one ray at a time).
  static bool packetKernelsAvailable();

 private:
  friend struct detail::PacketKernels;
  friend struct detail::ScreenTriangles;
  friend class FrameBins;
  using Triangle = detail::BvhTriangle;
  using Node = detail::BvhNode;
  void buildBvh() const;
  // Moves the triangles the drawn matrix culls out of triangles_ (constructor).
  void cullTriangles(const Scene& scene, const glm::dmat4& drawnClipFromWorld);
  // Builds the BVH once (thread-safe); there must be triangles. Queries one ray at a time walk it
  // only when usesBvh(); the packets of a binned frame whose rays stray build it for any count.
  void ensureBvh() const {
    if (!bvhBuilt()) std::call_once(bvh_->once, [this] { buildBvh(); });
  }
  // Triangles only, by the BVH when there is one; best.t is the current bound (the ray's tMax when
  // best.primitiveId == 0), updated in place.
  void closestTriangle(const Ray& worldRay, Hit& best) const noexcept;
  // The analytic primitives, linearly, with the same update rule.
  void closestAnalytic(const Ray& worldRay, Hit& best) const noexcept;
  // That rule for primitive p: bounded is the world ray, its tMax set to best.t here.
  void testAnalytic(std::size_t p, Ray& bounded, Hit& best) const noexcept;
  // Adds the analytic primitives to a tile's triangle hits (closestHit's update rule). With
  // `bins`, only those that may cover tile (tileX, tileY): every ray of the tile must stay on its
  // pixel (closestHitsTileBinned knows).
  void addAnalyticToTile(const Ray* rays, Hit* hits, std::size_t rowStride, int width, int height,
                         const FrameBins* bins = nullptr, int tileX = 0,
                         int tileY = 0) const noexcept;
  // closestHit without the analytic primitives (the packet kernels' one-ray fallback).
  Hit closestTriangleHit(const Ray& worldRay) const noexcept;

  glm::dvec3 reference_;
  double boxPad_ = 0.0;
  // The triangles queries test, in primitive id order: every triangle (triangles_[id - 1]) unless
  // face culling left some out; then allTriangles_[id - 1] holds every one and culled_[id - 1]
  // says which are left out.
  std::vector<Triangle> triangles_;
  std::vector<Triangle> allTriangles_;
  std::vector<std::uint8_t> culled_;
  std::size_t triangleIdCount_ = 0;
  const Triangle& triangleOfId(std::uint32_t primitiveId) const {
    return allTriangles_.empty() ? triangles_[primitiveId - 1] : allTriangles_[primitiveId - 1];
  }
  bool wantsBvh_ = false;
  // Built once (ensureBvh): the nodes, depth-first (the first child follows its parent), and a
  // copy of the triangles in leaf order, so that triangles_ keeps its order for the bins. Behind
  // a pointer so that the intersector stays movable.
  struct Bvh {
    std::once_flag once;
    std::atomic<bool> built{false};
    std::vector<Node> nodes;
    std::vector<Triangle> triangles;
  };
  std::unique_ptr<Bvh> bvh_ = std::make_unique<Bvh>();
  std::vector<AnalyticPrimitive> primitives_;  // primitive p has id firstAnalyticId_ + p
  std::uint32_t firstAnalyticId_ = 1;
};

}  // namespace clipray

#pragma once
// SIMD packet tracing behind SceneIntersector::closestHits (internal header): AVX2 kernels that
// trace four rays at once through the BVH or a tile's screen-space bins, with the scalar path's
// answers bit for bit.

#include <span>

#include "clipray/intersect/FrameBins.hpp"
#include "clipray/intersect/SceneIntersector.hpp"

namespace clipray::detail {

struct PacketKernels {
  // True when this CPU runs the AVX2 kernels (checked once).
  static bool available();
  // A tile of width * height <= SceneIntersector::kMaxPacket rays (rows rowStride apart);
  // the scene must have a BVH. Triangles only: hits are what closestHit would answer without the
  // analytic primitives, which the caller adds.
  static void trace(const SceneIntersector& scene, const Ray* rays, Hit* hits,
                    std::size_t rowStride, int width, int height) noexcept;
  // The same answer for tile (tileX, tileY) of bins' frame (rays and hits point at the tile's
  // first pixel): a packet whose rays all stay on their pixel centres' lines of sight tests the
  // triangles binned in the tile instead of walking the BVH. Returns whether every ray of the
  // tile that can hit anything went through the bins (no BVH walk, no ray one at a time).
  static bool traceBinned(const SceneIntersector& scene, const FrameBins& bins, int tileX,
                          int tileY, const Ray* rays, Hit* hits, std::size_t rowStride, int width,
                          int height) noexcept;
};

}  // namespace clipray::detail

#pragma once
// SIMD packet tracing behind SceneIntersector::closestHits (internal header).

#include <span>

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
};

}  // namespace clipray::detail

#pragma once
// The analytic primitives of a tile, four rays per AVX2 instruction (internal header): the
// operations of Primitives.cpp and of SceneIntersector's closest-hit update, in their order, so
// the same (t, id) bit for bit.

#include <cstddef>
#include <cstdint>

#include "clipray/intersect/SceneIntersector.hpp"

namespace clipray::detail {

// Whether this CPU runs the kernel (AVX2 and FMA) and the SIMD kernels are chosen.
bool primitiveKernelsAvailable();

// For rays[0..3] (finite or not), what SceneIntersector::addAnalyticToTile does for each: from
// hits[l] (the triangles' answer), each of the `count` primitives primitives[k] (id ids[k]) in
// turn with closestHit's update rule; a ray whose coordinates are not all finite is left alone.
void addPrimitivesToFour(const AnalyticPrimitive* const* primitives, const std::uint32_t* ids,
                         std::size_t count, const Ray* rays, Hit* hits) noexcept;

}  // namespace clipray::detail

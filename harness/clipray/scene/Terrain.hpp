#pragma once
// A reproducible terrain-like heightfield for benchmarks and the large scene of the suite: the
// same triangles on every platform for a given (triangle count, seed).

#include <cstddef>
#include <cstdint>
#include <string>

#include "clipray/scene/Scene.hpp"

namespace clipray {

// A heightfield over [-50, 50]^2 (y up) of 2 n^2 triangles, n = ceil(sqrt(minTriangles / 2)):
// rolling hills (sines) plus value noise and jitter from a 64-bit LCG seeded with `seed`.
MeshObject makeTerrainMesh(std::size_t minTriangles, std::uint64_t seed, std::string name);

}  // namespace clipray

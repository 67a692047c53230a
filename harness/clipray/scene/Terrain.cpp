#include "clipray/scene/Terrain.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace clipray {

MeshObject makeTerrainMesh(std::size_t minTriangles, std::uint64_t seed, std::string name) {
  const int cells =
      std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(minTriangles) / 2.0))));
  const int n = cells + 1;
  // An LCG (Knuth's MMIX constants) rather than <random>: its distributions are not specified
  // bit for bit, and the scene must be the same everywhere.
  std::uint64_t state = 0x9E3779B97F4A7C15ull ^ seed;
  auto random01 = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1p-53;
  };
  std::vector<double> noise(static_cast<std::size_t>(17 * 17));
  for (double& x : noise) x = random01();
  auto noiseAt = [&](double u, double v) {  // bilinear value noise on a 16x16 lattice
    const double fu = u * 16.0, fv = v * 16.0;
    const int i = std::min(15, static_cast<int>(fu)), j = std::min(15, static_cast<int>(fv));
    const double su = fu - i, sv = fv - j;
    auto at = [&](int a, int b) { return noise[static_cast<std::size_t>(b * 17 + a)]; };
    return (at(i, j) * (1 - su) + at(i + 1, j) * su) * (1 - sv) +
           (at(i, j + 1) * (1 - su) + at(i + 1, j + 1) * su) * sv;
  };
  MeshObject mesh;
  mesh.name = std::move(name);
  mesh.worldPositions.reserve(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double u = static_cast<double>(i) / cells;
      const double v = static_cast<double>(j) / cells;
      const double x = -50.0 + 100.0 * u, z = -50.0 + 100.0 * v;
      const double h = 3.0 * std::sin(x * 0.11) * std::cos(z * 0.07) +
                       1.5 * std::sin(x * 0.31 + 1.0) + 6.0 * noiseAt(u, v) + 0.3 * random01();
      mesh.worldPositions.emplace_back(x, h, z);
    }
  }
  mesh.triangles.reserve(static_cast<std::size_t>(cells) * cells * 2);
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const auto k = static_cast<std::uint32_t>(j * n + i);
      const auto row = static_cast<std::uint32_t>(n);
      mesh.triangles.emplace_back(k, k + row, k + 1);
      mesh.triangles.emplace_back(k + 1, k + row, k + row + 1);
    }
  }
  return mesh;
}

}  // namespace clipray

#pragma once
// Small scenes built in code for tests (the shipped ones live in scenes/).

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "clipray/scene/Scene.hpp"

namespace clipray::testing {

// A closed icosphere: shared vertices stored once, so shared edges are bit-identical.
inline MeshObject icosphere(const std::string& name, glm::dvec3 centre, double radius, int level) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<glm::u32vec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> cache;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = cache.find(key);
      if (it != cache.end()) return it->second;
      v.push_back(glm::normalize((v[a] + v[b]) * 0.5));
      const auto index = static_cast<std::uint32_t>(v.size() - 1);
      cache[key] = index;
      return index;
    };
    std::vector<glm::u32vec3> refined;
    for (const auto& tri : f) {
      const std::uint32_t ab = middle(tri.x, tri.y), bc = middle(tri.y, tri.z),
                          ca = middle(tri.z, tri.x);
      refined.insert(refined.end(),
                     {{tri.x, ab, ca}, {tri.y, bc, ab}, {tri.z, ca, bc}, {ab, bc, ca}});
    }
    f = refined;
  }
  MeshObject object;
  object.name = name;
  for (const auto& p : v) object.worldPositions.push_back(centre + radius * p);
  object.triangles = f;
  return object;
}

// The triangles of a grid of cells x cells quads over (cells + 1)^2 vertices stored row by row,
// two per quad with the shared diagonal.
inline std::vector<glm::u32vec3> gridTriangles(int cells) {
  std::vector<glm::u32vec3> triangles;
  const auto n = static_cast<std::uint32_t>(cells + 1);
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const auto k = static_cast<std::uint32_t>(j) * n + static_cast<std::uint32_t>(i);
      triangles.emplace_back(k, k + n, k + 1);
      triangles.emplace_back(k + 1, k + n, k + n + 1);
    }
  }
  return triangles;
}

inline MeshObject quad(const std::string& name, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c,
                       glm::dvec3 d) {
  MeshObject object;
  object.name = name;
  object.worldPositions = {a, b, c, d};
  object.triangles = {{0, 1, 2}, {0, 2, 3}};
  return object;
}

}  // namespace clipray::testing

// triangulatePolygon: ear clipping in the plane of Newell's normal (see PolygonTriangulation.hpp).

#include "clipray/scene/loaders/PolygonTriangulation.hpp"

#include <algorithm>
#include <cmath>

namespace clipray::meshfiles {
namespace {

double cross2(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// p inside or on the counter-clockwise triangle abc.
bool inTriangle(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}

}  // namespace

PolygonTriangles triangulatePolygon(std::span<const glm::dvec3> corners) {
  PolygonTriangles result;
  const std::size_t n = corners.size();
  if (n < 3) return result;
  // Newell's normal: the polygon's area vector, exact in direction for a planar polygon and the
  // least-squares plane's normal otherwise.
  glm::dvec3 normal(0.0), centroid(0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const glm::dvec3& a = corners[k];
    const glm::dvec3& b = corners[(k + 1) % n];
    normal +=
        glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    centroid += a;
  }
  centroid /= static_cast<double>(n);
  const double normalLength = glm::length(normal);
  double diameter = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t j = k + 1; j < n; ++j) {
      diameter = std::max(diameter, glm::length(corners[k] - corners[j]));
    }
  }
  const auto fan = [&](std::vector<std::size_t> remaining) {
    for (std::size_t k = 1; k + 1 < remaining.size(); ++k) {
      result.triangles.push_back({remaining[0], remaining[k], remaining[k + 1]});
    }
  };
  if (!(normalLength > 0.0) || !std::isfinite(normalLength) || n == 3) {
    // No area (all corners on a line) or a triangle: nothing to choose.
    std::vector<std::size_t> all(n);
    for (std::size_t k = 0; k < n; ++k) all[k] = k;
    fan(all);
    return result;
  }
  const glm::dvec3 unitNormal = normal / normalLength;
  double farthest = 0.0;
  for (const glm::dvec3& p : corners) {
    farthest = std::max(farthest, std::abs(glm::dot(p - centroid, unitNormal)));
  }
  result.nonPlanarity = diameter > 0.0 ? farthest / diameter : 0.0;

  // 2D coordinates in the plane, oriented so that the polygon runs counter-clockwise.
  glm::dvec3 u = std::abs(unitNormal.x) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  u = glm::normalize(glm::cross(u, unitNormal));
  const glm::dvec3 v = glm::cross(unitNormal, u);
  std::vector<glm::dvec2> flat(n);
  for (std::size_t k = 0; k < n; ++k) {
    const glm::dvec3 d = corners[k] - centroid;
    flat[k] = {glm::dot(d, u), glm::dot(d, v)};
  }

  std::vector<std::size_t> remaining(n);
  for (std::size_t k = 0; k < n; ++k) remaining[k] = k;
  while (remaining.size() > 3) {
    const std::size_t m = remaining.size();
    bool clipped = false;
    // From the second corner on: a convex polygon comes out as the fan from its first corner.
    for (std::size_t step = 0; step < m && !clipped; ++step) {
      const std::size_t k = (step + 1) % m;
      const std::size_t previous = remaining[(k + m - 1) % m], current = remaining[k],
                        next = remaining[(k + 1) % m];
      const glm::dvec2 a = flat[previous], b = flat[current], c = flat[next];
      if (!(cross2(a, b, c) > 0.0)) continue;  // reflex or flat: not an ear
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        const std::size_t other = remaining[j];
        if (other == previous || other == current || other == next) continue;
        // A corner at the same place as one of the ear's (a polygon touching itself) does not
        // block it.
        const glm::dvec2 p = flat[other];
        if (p == a || p == b || p == c) continue;
        empty = !inTriangle(p, a, b, c);
      }
      if (!empty) continue;
      result.triangles.push_back({previous, current, next});
      remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) {
      result.fanFallback = true;
      fan(remaining);
      return result;
    }
  }
  result.triangles.push_back({remaining[0], remaining[1], remaining[2]});
  return result;
}

}  // namespace clipray::meshfiles

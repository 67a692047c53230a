#include "clipray/compare/DrawCallIds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "clipray/intersect/Watertight.hpp"
#include "clipray/rays/RobustRays.hpp"

namespace clipray {

namespace {

// Squared distance from p to the segment ab.
double segmentDistance2(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double length2 = glm::dot(ab, ab);
  const double s = length2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
  const glm::dvec2 d = p - (a + s * ab);
  return glm::dot(d, d);
}

// Squared window-space distance from the pixel centre to the triangle's projection (0 inside);
// infinity for a triangle with a vertex on or behind the eye's plane (w <= 0).
double projectedDistance2(const glm::dmat4& clipFromWorld, Viewport viewport, glm::dvec2 centre,
                          const glm::dvec3 (&corners)[3]) {
  glm::dvec2 window[3];
  for (int k = 0; k < 3; ++k) {
    const glm::dvec4 clip = clipFromWorld * glm::dvec4(corners[k], 1.0);
    if (!(clip.w > 0.0)) return std::numeric_limits<double>::infinity();
    window[k] = {(clip.x / clip.w * 0.5 + 0.5) * viewport.width,
                 (clip.y / clip.w * 0.5 + 0.5) * viewport.height};
  }
  const auto edge = [&](int a, int b) {
    const glm::dvec2 e = window[b] - window[a], p = centre - window[a];
    return e.x * p.y - e.y * p.x;
  };
  const double e0 = edge(0, 1), e1 = edge(1, 2), e2 = edge(2, 0);
  if ((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0)) return 0.0;
  return std::min({segmentDistance2(centre, window[0], window[1]),
                   segmentDistance2(centre, window[1], window[2]),
                   segmentDistance2(centre, window[2], window[0])});
}

}  // namespace

std::vector<std::uint32_t> idsFromDrawCalls(const Scene& scene, const PickingCamera& camera,
                                            const std::vector<std::uint8_t>& meshOfPixel,
                                            const AnalyticFrame& analytic) {
  const PrimitiveIdTable table(scene);
  const Viewport viewport = camera.viewport;
  const RobustRayGenerator rays(camera.clipFromWorld, camera.mode, camera.clipPlanes,
                                depthClampRays(camera));
  std::vector<std::uint32_t> ids(meshOfPixel.size(), 0);
  for (std::size_t i = 0; i < meshOfPixel.size(); ++i) {
    if (meshOfPixel[i] == 0) continue;
    const std::size_t mesh = meshOfPixel[i] - 1u;
    const MeshObject& object = scene.objects.at(mesh);
    const std::uint32_t rayId = analytic.hits[i].primitiveId;
    if (rayId != 0 && table.decode(rayId).object == static_cast<int>(mesh)) {
      ids[i] = rayId;
      continue;
    }
    const int x = static_cast<int>(i % static_cast<std::size_t>(viewport.width));
    const int y = static_cast<int>(i / static_cast<std::size_t>(viewport.width));
    const Ray sight = rays.generateForPixel(x, y, viewport);
    const glm::dvec2 centre(x + 0.5, y + 0.5);
    std::uint32_t best = 0;
    double bestT = std::numeric_limits<double>::infinity();
    double bestDistance2 = std::numeric_limits<double>::infinity();
    const WatertightRay watertight(sight.origin, sight.direction);
    for (std::uint32_t t = 0; t < object.triangles.size(); ++t) {
      const glm::u32vec3 triangle = object.triangles[t];
      const glm::dvec3 corners[3] = {object.worldPositions[triangle.x],
                                     object.worldPositions[triangle.y],
                                     object.worldPositions[triangle.z]};
      if (sight.tMax >= 0.0) {
        if (const auto hit =
                intersectTriangle(watertight, sight.tMax, corners[0], corners[1], corners[2])) {
          if (*hit < bestT) {
            bestT = *hit;
            best = t;
          }
          continue;
        }
      }
      if (bestT < std::numeric_limits<double>::infinity()) continue;  // a hit beats any distance
      const double distance2 = projectedDistance2(camera.clipFromWorld, viewport, centre, corners);
      if (distance2 < bestDistance2) {
        bestDistance2 = distance2;
        best = t;
      }
    }
    ids[i] = table.firstIdOfObject[mesh] + best;
  }
  return ids;
}

}  // namespace clipray

#include "clipray/engine/DepthRangeGroups.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "clipray/compare/DepthMapping.hpp"
#include "clipray/compare/PolygonOffset.hpp"
#include "clipray/intersect/SceneIntersector.hpp"

namespace clipray::engine {

std::vector<DepthRangeGroup> depthRangeGroups(const Scene& scene) {
  std::vector<DepthRangeGroup> groups{{scene.depthRange, std::nullopt, {}, true}};
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const glm::dvec2 range = scene.objects[k].depthRangeOr(scene.depthRange);
    const std::optional<PolygonOffset>& offset = scene.objects[k].polygonOffset;
    auto group = std::find_if(groups.begin(), groups.end(), [&](const DepthRangeGroup& g) {
      return g.range == range && g.offset == offset;
    });
    if (group == groups.end()) group = groups.insert(groups.end(), {range, offset, {}, false});
    group->objects.push_back(k);
  }
  return groups;
}

namespace {

// The group's objects (and the analytic primitives for the scene's group) as a scene of their own,
// with the map from its primitive ids to the whole scene's.
struct GroupScene {
  Scene scene;
  std::vector<std::uint32_t> globalIdOfLocal;  // index: the group scene's id; [0] = 0
};

GroupScene groupScene(const Scene& whole, const DepthRangeGroup& group) {
  GroupScene out;
  out.scene.depthRange = whole.depthRange;
  for (const std::size_t k : group.objects) out.scene.objects.push_back(whole.objects[k]);
  if (group.analytic) out.scene.primitives = whole.primitives;
  const PrimitiveIdTable wholeIds(whole);
  out.globalIdOfLocal.push_back(0);
  for (const std::size_t k : group.objects) {
    for (std::uint32_t t = 0; t < whole.objects[k].triangles.size(); ++t) {
      out.globalIdOfLocal.push_back(wholeIds.firstIdOfObject[k] + t);
    }
  }
  if (group.analytic) {
    for (std::uint32_t p = 0; p < wholeIds.analyticCount; ++p) {
      out.globalIdOfLocal.push_back(wholeIds.firstAnalyticId + p);
    }
  }
  return out;
}

// Per primitive id of the group's scene, the offset its hits compete with: the middle of what GL
// allows (PolygonOffset.hpp) with a 24-bit buffer's r, whatever the run's format (the hits are
// traced once for every format; the middle's sign, which decides coplanar surfaces, is the
// format's). Empty for a group without an offset.
std::vector<double> offsetsOf(const GroupScene& part, const DepthRangeGroup& group,
                              const DepthMapping& mapping, const PickingCamera& camera,
                              Viewport viewport) {
  std::vector<double> offsets;
  if (!group.offset) return offsets;
  offsets.push_back(0.0);  // id 0: no primitive
  const glm::dvec2 size(viewport.width, viewport.height);
  for (const MeshObject& object : part.scene.objects) {
    for (const glm::u32vec3& t : object.triangles) {
      glm::dvec4 clip[3];
      for (int v = 0; v < 3; ++v) {
        clip[v] = camera.clipFromWorld * glm::dvec4(object.worldPositions[t[v]], 1.0);
      }
      const glm::dvec2 gradient =
          windowDepthGradient(clip[0], clip[1], clip[2], size, mapping.windowFromNdcScale());
      offsets.push_back(
          std::isfinite(gradient.x)
              ? offsetInterval(*group.offset, gradient.x, gradient.y, 1.0, DepthFormat::Unorm24)
                    .middle()
              : 0.0);
    }
  }
  return offsets;
}

}  // namespace

void intersectByDepthRange(AnalyticFrame& frame, const SceneIntersector& wholeScene,
                           const Scene& scene, const glm::dmat4& drawnClipFromWorld,
                           const PickingCamera& camera, unsigned threadCount) {
  const std::vector<DepthRangeGroup> groups = depthRangeGroups(scene);
  if (groups.size() == 1) {
    intersectFrame(frame, wholeScene, camera, threadCount);
    return;
  }
  const glm::dvec3& reference = wholeScene.reference();
  const bool greater = nearerIsGreater(camera.mode, scene.depthRange);
  const int width = frame.viewport.width;
  FrameVector<Hit> kept;
  std::vector<double> keptDepth;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const GroupScene part = groupScene(scene, groups[g]);
    const SceneIntersector intersector(
        part.scene, reference, SceneIntersector::BvhBuild::WhenFirstNeeded, drawnClipFromWorld);
    frame.hits = {};
    intersectFrame(frame, intersector, camera, threadCount);
    const DepthMapping mapping{camera.mode, groups[g].range, false};
    const std::vector<double> offsets = offsetsOf(part, groups[g], mapping, camera, frame.viewport);
    if (g == 0) {
      kept.resize(frame.pixelCount());
      keptDepth.assign(frame.pixelCount(), 0.0);
    }
    parallelForRows(frame.viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
      std::vector<Ray> rowRays(frame.pixelCentreRays ? static_cast<std::size_t>(width) : 0);
      for (int y = rowBegin; y < rowEnd; ++y) {
        const std::size_t first = static_cast<std::size_t>(y) * width;
        if (frame.pixelCentreRays) frame.pixelCentreRays->row(y, 0, width, rowRays.data());
        const Ray* rays = frame.pixelCentreRays ? rowRays.data() : frame.rays.data() + first;
        for (int x = 0; x < width; ++x) {
          const std::size_t i = first + static_cast<std::size_t>(x);
          Hit hit = frame.hits[i];
          if (!hit.hit()) {
            if (g == 0) kept[i] = hit;
            continue;
          }
          hit.primitiveId = part.globalIdOfLocal[hit.primitiveId];
          const Ray& ray = rays[x];
          const glm::dvec4 clip =
              camera.clipFromWorld * glm::dvec4(ray.origin + hit.t * ray.direction, 1.0);
          const double depth = mapping.windowDepth(clip.z / clip.w) +
                               (offsets.empty() ? 0.0 : offsets[frame.hits[i].primitiveId]);
          const bool wins = g == 0 || !kept[i].hit() ||
                            (greater ? depth > keptDepth[i] : depth < keptDepth[i]) ||
                            (depth == keptDepth[i] && hit.primitiveId < kept[i].primitiveId);
          if (wins) {
            kept[i] = hit;
            keptDepth[i] = depth;
          }
        }
      }
    });
  }
  frame.hits = std::move(kept);
}

}  // namespace clipray::engine

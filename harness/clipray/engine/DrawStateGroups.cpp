#include "clipray/engine/DrawStateGroups.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "clipray/compare/DepthMapping.hpp"
#include "clipray/compare/PolygonOffset.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/AnalyticChoice.hpp"

namespace clipray::engine {

std::vector<DrawStateGroup> drawStateGroups(const Scene& scene) {
  std::vector<DrawStateGroup> groups{{scene.depthRange, {}, std::nullopt, {}, true}};
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const MeshObject& object = scene.objects[k];
    const glm::dvec2 range = object.depthRangeOr(scene.depthRange);
    auto group = std::find_if(groups.begin(), groups.end(), [&](const DrawStateGroup& g) {
      return g.range == range && g.clipPlanes == object.clipPlanes &&
             g.offset == object.polygonOffset;
    });
    if (group == groups.end()) {
      group =
          groups.insert(groups.end(), {range, object.clipPlanes, object.polygonOffset, {}, false});
    }
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

GroupScene groupScene(const Scene& whole, const DrawStateGroup& group) {
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

// The frame's rays cut by the group's own planes (the camera's cut them already): clipray's
// pixel-centre rays made for the camera with both sets of planes, or a copy of the stored rays
// cut once more.
AnalyticFrame groupFrame(const AnalyticFrame& frame, const PickingCamera& camera,
                         const std::vector<glm::dvec4>& planes) {
  if (frame.pixelCentreRays) {
    PickingCamera cut = camera;
    cut.clipPlanes.insert(cut.clipPlanes.end(), planes.begin(), planes.end());
    return robustRayFrame(cut);
  }
  AnalyticFrame out;
  out.viewport = frame.viewport;
  out.rays = frame.rays;
  for (Ray& ray : out.rays) cutToClipPlanes(ray, planes);
  return out;
}

// Per primitive id of the group's scene, the offset its hits compete with: the middle of what GL
// allows (compare/PolygonOffset.hpp) with a 24-bit buffer's r, whatever the run's format (the
// hits are traced once for every format; the middle's sign, which decides coplanar surfaces, is
// the format's). Empty for a group without an offset.
std::vector<double> offsetsOf(const GroupScene& part, const DrawStateGroup& group,
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

// Whether a group's hit at `depth` (window depth, offset included) is the one the depth test keeps
// over what is kept so far: the nearer under the test's direction, ties to the smaller primitive
// id (the object drawn first).
bool depthTestKeeps(const Hit& hit, double depth, const Hit& kept, double keptDepth, bool greater) {
  return !kept.hit() || (greater ? depth > keptDepth : depth < keptDepth) ||
         (depth == keptDepth && hit.primitiveId < kept.primitiveId);
}

// Whether the chosen path takes the screen path for this many triangles over this many pixels.
bool takesScreenPath(AnalyticPath path, std::size_t triangles, std::size_t pixels) {
  return path == AnalyticPath::Screen ||
         (path == AnalyticPath::Auto &&
          static_cast<double>(pixels) >= kScreenPixelsPerTriangle * static_cast<double>(triangles));
}

// Why --analytic auto leaves a frame of these counts to the rays.
std::string fewPixelsReason(std::size_t triangles, std::size_t pixels) {
  return std::to_string(triangles) + " triangles for " + std::to_string(pixels) +
         " pixels: the rays are faster below " +
         std::to_string(static_cast<int>(kScreenPixelsPerTriangle)) + " pixels a triangle";
}

}  // namespace

Hit closestHitByDrawState(const Ray& ray, const SceneIntersector& wholeScene, const Scene& scene,
                          const glm::dmat4& drawnClipFromWorld, const PickingCamera& camera) {
  const std::vector<DrawStateGroup> groups = drawStateGroups(scene);
  if (groups.size() == 1) return wholeScene.closestHit(ray);
  const bool greater = nearerIsGreater(camera.mode, scene.depthRange);
  Hit kept;
  double keptDepth = 0.0;
  for (const DrawStateGroup& group : groups) {
    const GroupScene part = groupScene(scene, group);
    const SceneIntersector intersector(part.scene, wholeScene.reference(),
                                       SceneIntersector::BvhBuild::WhenFirstNeeded,
                                       drawnClipFromWorld);
    Ray cut = ray;
    cutToClipPlanes(cut, group.clipPlanes);
    Hit hit = intersector.closestHit(cut);
    if (!hit.hit()) continue;
    const DepthMapping mapping{camera.mode, group.range, false};
    const std::vector<double> offsets = offsetsOf(part, group, mapping, camera, camera.viewport);
    const double offset = offsets.empty() ? 0.0 : offsets[hit.primitiveId];
    hit.primitiveId = part.globalIdOfLocal[hit.primitiveId];
    const glm::dvec3 point = cut.origin + hit.t * cut.direction;
    hit.t = glm::dot(point - ray.origin, ray.direction) / glm::dot(ray.direction, ray.direction);
    const glm::dvec4 clip = camera.clipFromWorld * glm::dvec4(point, 1.0);
    const double depth = mapping.windowDepth(clip.z / clip.w) + offset;
    if (depthTestKeeps(hit, depth, kept, keptDepth, greater)) {
      kept = hit;
      keptDepth = depth;
    }
  }
  return kept;
}

ScreenEvaluation intersectByDrawState(AnalyticFrame& frame, const SceneIntersector& wholeScene,
                                      const Scene& scene, const glm::dmat4& drawnClipFromWorld,
                                      const PickingCamera& camera, unsigned threadCount) {
  const std::vector<DrawStateGroup> groups = drawStateGroups(scene);
  // An app's own picking rays (stored per pixel) are the ray path's alone.
  const AnalyticPath path = frame.pixelCentreRays ? chosenAnalyticPath() : AnalyticPath::Rays;
  if (groups.size() == 1) {
    if (takesScreenPath(path, wholeScene.triangleCount(), frame.pixelCount())) {
      // Decided pixels keep their planes: the compare evaluates them in place of rays.
      return intersectFrameInScreenSpace(frame, wholeScene, camera, threadCount, nullptr,
                                         DecidedHits::FromPlanes);
    }
    intersectFrame(frame, wholeScene, camera, threadCount);
    ScreenEvaluation rays;
    if (path == AnalyticPath::Auto) {
      rays.reason = fewPixelsReason(wholeScene.triangleCount(), frame.pixelCount());
    }
    return rays;
  }
  const glm::dvec3& reference = wholeScene.reference();
  const bool greater = nearerIsGreater(camera.mode, scene.depthRange);
  const int width = frame.viewport.width;
  FrameVector<Hit> kept(frame.pixelCount());
  std::vector<double> keptDepth(frame.pixelCount(), 0.0);
  // The groups' frames the screen path evaluated, their counts summed; else the first reason.
  ScreenEvaluation evaluated;
  evaluated.frames = 0;
  evaluated.groups = groups.size();
  std::string firstReason;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const GroupScene part = groupScene(scene, groups[g]);
    const SceneIntersector intersector(
        part.scene, reference, SceneIntersector::BvhBuild::WhenFirstNeeded, drawnClipFromWorld);
    const bool ownRays = !groups[g].clipPlanes.empty();
    AnalyticFrame cutFrame = ownRays
                                 ? groupFrame(frame, camera, groups[g].clipPlanes)
                                 : AnalyticFrame{frame.viewport, {}, frame.pixelCentreRays, {}, {}};
    if (!ownRays && !frame.pixelCentreRays) cutFrame.rays = frame.rays;
    // The group's hits, bit for bit the ray path's on either path: decided pixels are tested
    // (their t competes in the depth test below).
    if (takesScreenPath(path, intersector.triangleCount(), frame.pixelCount())) {
      PickingCamera groupCamera = camera;
      if (ownRays) {
        groupCamera.clipPlanes.insert(groupCamera.clipPlanes.end(), groups[g].clipPlanes.begin(),
                                      groups[g].clipPlanes.end());
      }
      const ScreenEvaluation e = intersectFrameInScreenSpace(
          cutFrame, intersector, groupCamera, threadCount, nullptr, DecidedHits::Tested);
      if (e.used) {
        evaluated.used = true;
        evaluated.background += e.background;
        evaluated.decided += e.decided;
        evaluated.contested += e.contested;
        evaluated.traced += e.traced;
        evaluated.boundMisses += e.boundMisses;
        evaluated.rayDeviationNdc = std::max(evaluated.rayDeviationNdc, e.rayDeviationNdc);
        ++evaluated.frames;
      } else if (firstReason.empty()) {
        firstReason = e.reason;
      }
    } else {
      intersectFrame(cutFrame, intersector, camera, threadCount);
      if (path == AnalyticPath::Auto && firstReason.empty()) {
        firstReason = fewPixelsReason(intersector.triangleCount(), frame.pixelCount());
      }
    }
    const DepthMapping mapping{camera.mode, groups[g].range, false};
    const std::vector<double> offsets = offsetsOf(part, groups[g], mapping, camera, frame.viewport);
    parallelForRows(frame.viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
      // A row goes in runs of 64 pixels; a run with no hit of the group computes no ray. The
      // group's rays are the frame's where it has no planes of its own; where its planes cut
      // them, the frame's are computed too (t is measured along them).
      constexpr int kRun = 64;
      std::array<Ray, kRun> frameRun, groupRun;
      for (int y = rowBegin; y < rowEnd; ++y) {
        for (int x0 = 0; x0 < width; x0 += kRun) {
          const int n = std::min(kRun, width - x0);
          const std::size_t first = static_cast<std::size_t>(y) * width + x0;
          if (g == 0) std::fill_n(kept.data() + first, n, Hit{});
          bool anyHit = false;
          for (int k = 0; k < n; ++k) anyHit = anyHit || cutFrame.hits[first + k].hit();
          if (!anyHit) continue;
          const Ray* groupRays = groupRun.data();
          if (cutFrame.pixelCentreRays) {
            cutFrame.pixelCentreRays->row(y, x0, n, groupRun.data());
          } else {
            groupRays = cutFrame.rays.data() + first;
          }
          const Ray* frameRays = groupRays;
          if (ownRays && frame.pixelCentreRays) {
            frame.pixelCentreRays->row(y, x0, n, frameRun.data());
            frameRays = frameRun.data();
          } else if (ownRays) {
            frameRays = frame.rays.data() + first;
          }
          for (int k = 0; k < n; ++k) {
            const std::size_t i = first + static_cast<std::size_t>(k);
            Hit hit = cutFrame.hits[i];
            if (!hit.hit()) continue;
            const double offset = offsets.empty() ? 0.0 : offsets[hit.primitiveId];
            hit.primitiveId = part.globalIdOfLocal[hit.primitiveId];
            const Ray& groupRay = groupRays[k];
            const glm::dvec3 point = groupRay.origin + hit.t * groupRay.direction;
            if (ownRays) {
              // The group's ray starts where its planes cut the frame's: t along the frame's ray.
              const Ray& frameRay = frameRays[k];
              hit.t = glm::dot(point - frameRay.origin, frameRay.direction) /
                      glm::dot(frameRay.direction, frameRay.direction);
            }
            const glm::dvec4 clip = camera.clipFromWorld * glm::dvec4(point, 1.0);
            const double depth = mapping.windowDepth(clip.z / clip.w) + offset;
            if (depthTestKeeps(hit, depth, kept[i], keptDepth[i], greater)) {
              kept[i] = hit;
              keptDepth[i] = depth;
            }
          }
        }
      }
    });
  }
  frame.hits = std::move(kept);
  if (evaluated.used) return evaluated;
  ScreenEvaluation rays;
  if (path != AnalyticPath::Rays) {
    rays.reason = "objects with draw state of their own (" + std::to_string(groups.size()) +
                  " groups), none on the screen path: " + firstReason;
  }
  return rays;
}

}  // namespace clipray::engine

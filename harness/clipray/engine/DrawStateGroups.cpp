#include "clipray/engine/DrawStateGroups.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "clipray/compare/DepthMapping.hpp"
#include "clipray/compare/PolygonOffset.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/AnalyticChoice.hpp"

namespace clipray::engine {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

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

namespace {

// One group's pass over the frame: its objects as a scene with its own intersector, its rays (the
// frame's, or cut by its own planes) and their hits (by its scene's ids), and how its hits compete
// in the depth test.
struct GroupPass {
  GroupScene part;
  std::unique_ptr<SceneIntersector> intersector;
  AnalyticFrame frame;
  bool ownRays = false;
  DepthMapping mapping;
  std::vector<double> offsets;  // offsetsOf
};

// A group's hit at one pixel in the depth test: the hit (the whole scene's id; t NaN where it was
// decided from its planes), the window depth the test compares (offset included) and how far the
// ray path's may lie from it (0: that depth).
struct Contender {
  Hit hit;
  double depth = 0.0, reach = 0.0;
  std::size_t group = 0;
  std::uint32_t localId = 0;
};

// The decided triangles' planes by the whole scene's ids (each group's entries copied as bytes:
// only its decided triangles' are written).
std::shared_ptr<FrameVector<TrianglePlanes>> planesByWholeSceneId(
    const std::vector<std::unique_ptr<GroupPass>>& passes, std::uint32_t primitiveIdCount) {
  auto planes = std::make_shared<FrameVector<TrianglePlanes>>();
  planes->resize(std::size_t{primitiveIdCount} + 1);
  for (const std::unique_ptr<GroupPass>& pass : passes) {
    if (!pass->frame.planesById) continue;
    const std::vector<std::uint32_t>& globalIds = pass->part.globalIdOfLocal;
    for (std::size_t local = 1; local < globalIds.size(); ++local) {
      std::memcpy(&(*planes)[globalIds[local]], &(*pass->frame.planesById)[local],
                  sizeof(TrianglePlanes));
    }
  }
  return planes;
}

// Per pixel, the group hit the depth test keeps (greater: GL_GREATER), by the whole scene's ids, t
// along the frame's ray (NaN where it was decided from its group's planes).
FrameVector<Hit> keptHits(const AnalyticFrame& frame,
                          const std::vector<std::unique_ptr<GroupPass>>& passes,
                          const PickingCamera& camera, bool greater, unsigned threadCount) {
  const Viewport viewport = frame.viewport;
  const int width = viewport.width;
  FrameVector<Hit> kept(frame.pixelCount());
  std::vector<double> clipX(static_cast<std::size_t>(width));
  for (int x = 0; x < width; ++x) {
    clipX[static_cast<std::size_t>(x)] = clipXYOfPixelCentre(x, 0, viewport).x;
  }
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    // A row goes in runs of 64 pixels. A run's rays (the frame's, and each group's with planes of
    // its own) are computed where a pixel needs one: two groups' hits there, one of them with its
    // t (its depth is measured along its ray) or both from planes the depth test leaves open, or
    // a hit along a group's own ray, whose t is given along the frame's.
    constexpr int kRun = 64;
    std::array<Ray, kRun> frameRun;
    std::vector<std::array<Ray, kRun>> groupRuns(passes.size());
    std::vector<const Ray*> groupRays(passes.size());
    for (int y = rowBegin; y < rowEnd; ++y) {
      const double yNdc = clipXYOfPixelCentre(0, y, viewport).y;
      for (int x0 = 0; x0 < width; x0 += kRun) {
        const int n = std::min(kRun, width - x0);
        const std::size_t first = static_cast<std::size_t>(y) * width + x0;
        std::fill_n(kept.data() + first, n, Hit{});
        bool anyHit = false;
        for (const std::unique_ptr<GroupPass>& pass : passes) {
          for (int k = 0; k < n; ++k) {
            anyHit = anyHit || pass->frame.hits[first + static_cast<std::size_t>(k)].hit();
          }
        }
        if (!anyHit) continue;
        const Ray* frameRays = nullptr;
        const auto makeRays = [&] {
          if (frameRays) return;
          if (frame.pixelCentreRays) {
            frame.pixelCentreRays->row(y, x0, n, frameRun.data());
            frameRays = frameRun.data();
          } else {
            frameRays = frame.rays.data() + first;
          }
          for (std::size_t g = 0; g < passes.size(); ++g) {
            const GroupPass& pass = *passes[g];
            if (!pass.ownRays) {
              groupRays[g] = frameRays;
            } else if (pass.frame.pixelCentreRays) {
              pass.frame.pixelCentreRays->row(y, x0, n, groupRuns[g].data());
              groupRays[g] = groupRuns[g].data();
            } else {
              groupRays[g] = pass.frame.rays.data() + first;
            }
          }
        };
        // A group's hit with its t: its depth at the point along its ray, t given along the
        // frame's ray (the group's ray starts where its planes cut the frame's).
        const auto traced = [&](std::size_t g, Hit hit, int k) {
          makeRays();
          const GroupPass& pass = *passes[g];
          Contender c{hit, 0.0, 0.0, g, hit.primitiveId};
          const double offset = pass.offsets.empty() ? 0.0 : pass.offsets[hit.primitiveId];
          c.hit.primitiveId = pass.part.globalIdOfLocal[hit.primitiveId];
          const Ray& groupRay = groupRays[g][k];
          const glm::dvec3 point = groupRay.origin + hit.t * groupRay.direction;
          if (pass.ownRays) {
            const Ray& frameRay = frameRays[k];
            c.hit.t = glm::dot(point - frameRay.origin, frameRay.direction) /
                      glm::dot(frameRay.direction, frameRay.direction);
          }
          const glm::dvec4 clip = camera.clipFromWorld * glm::dvec4(point, 1.0);
          c.depth = pass.mapping.windowDepth(clip.z / clip.w) + offset;
          return c;
        };
        // A group's hit decided from its planes: its depth from the depth plane at the pixel
        // centre. The ray path's NDC z lies within twice the plane's bound of it (as the compare
        // takes it, PlaneClassification.cpp); the mapping and the offset round by far less than
        // 2^-40 of the depth.
        const auto fromPlanes = [&](std::size_t g, const Hit& hit, double xNdc) {
          const GroupPass& pass = *passes[g];
          const TrianglePlanes& p = (*pass.frame.planesById)[hit.primitiveId];
          Contender c{hit, 0.0, 0.0, g, hit.primitiveId};
          c.hit.primitiveId = pass.part.globalIdOfLocal[hit.primitiveId];
          const double offset = pass.offsets.empty() ? 0.0 : pass.offsets[hit.primitiveId];
          const double zNdc = p.za * xNdc + (p.zb * yNdc + p.zc);
          c.depth = pass.mapping.windowDepth(zNdc) + offset;
          c.reach = 2.0 * p.depthError * std::abs(pass.mapping.windowFromNdcScale()) +
                    0x1p-40 * std::abs(c.depth);
          if (!std::isfinite(c.depth) || !std::isfinite(c.reach)) c.reach = kInfinity;
          return c;
        };
        // A contender from planes made the ray path's: its triangle's test along its group's ray,
        // or the group's closest hit should that miss; false where nothing is hit.
        const auto made = [&](Contender& c, int k) {
          if (c.reach == 0.0) return true;
          makeRays();
          const GroupPass& pass = *passes[c.group];
          Hit hit = pass.intersector->intersectOne(c.localId, groupRays[c.group][k]);
          if (!hit.hit()) hit = pass.intersector->closestHit(groupRays[c.group][k]);
          if (!hit.hit()) return false;
          c = traced(c.group, hit, k);
          return true;
        };
        for (int k = 0; k < n; ++k) {
          const std::size_t i = first + static_cast<std::size_t>(k);
          std::size_t hitCount = 0, only = 0;
          for (std::size_t g = 0; g < passes.size(); ++g) {
            if (passes[g]->frame.hits[i].hit()) {
              ++hitCount;
              only = g;
            }
          }
          if (hitCount == 0) continue;
          if (hitCount == 1) {
            // One group's hit: kept, with no depth to compare (t along the frame's ray).
            const GroupPass& pass = *passes[only];
            Hit hit = pass.frame.hits[i];
            if (pass.ownRays && !std::isnan(hit.t)) {
              hit = traced(only, hit, k).hit;
            } else {
              hit.primitiveId = pass.part.globalIdOfLocal[hit.primitiveId];
            }
            kept[i] = hit;
            continue;
          }
          const double xNdc = clipX[static_cast<std::size_t>(x0 + k)];
          std::optional<Contender> best;
          for (std::size_t g = 0; g < passes.size(); ++g) {
            const Hit& hit = passes[g]->frame.hits[i];
            if (!hit.hit()) continue;
            Contender c = std::isnan(hit.t) ? fromPlanes(g, hit, xNdc) : traced(g, hit, k);
            if (!best) {
              best = c;
              continue;
            }
            // Surely kept or surely not where the reaches leave the depths apart; else both
            // depths the ray path's, and its test.
            const double gap = c.reach + best->reach;
            const double ahead = greater ? c.depth - best->depth : best->depth - c.depth;
            bool keeps = false;
            if (gap > 0.0 && ahead > gap) {
              keeps = true;
            } else if (gap > 0.0 && -ahead > gap) {
              keeps = false;
            } else {
              const bool bestMade = made(*best, k), candidateMade = made(c, k);
              if (!candidateMade) continue;
              keeps = !bestMade || depthTestKeeps(c.hit, c.depth, best->hit, best->depth, greater);
            }
            if (keeps) best = c;
          }
          if (best) kept[i] = best->hit;
        }
      }
    }
  });
  return kept;
}

}  // namespace

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
  // The groups' frames the screen path evaluated, their counts summed; else the first reason.
  ScreenEvaluation evaluated;
  evaluated.frames = 0;
  evaluated.groups = groups.size();
  std::string firstReason;
  std::vector<std::unique_ptr<GroupPass>> passes;
  bool anyPlanes = false;
  for (const DrawStateGroup& group : groups) {
    GroupPass& pass = *passes.emplace_back(std::make_unique<GroupPass>());
    pass.part = groupScene(scene, group);
    pass.intersector = std::make_unique<SceneIntersector>(
        pass.part.scene, reference, SceneIntersector::BvhBuild::WhenFirstNeeded,
        drawnClipFromWorld);
    const SceneIntersector& intersector = *pass.intersector;
    pass.ownRays = !group.clipPlanes.empty();
    pass.frame = pass.ownRays ? groupFrame(frame, camera, group.clipPlanes)
                              : AnalyticFrame{frame.viewport, {}, frame.pixelCentreRays, {}, {}};
    if (!pass.ownRays && !frame.pixelCentreRays) pass.frame.rays = frame.rays;
    if (takesScreenPath(path, intersector.triangleCount(), frame.pixelCount())) {
      PickingCamera groupCamera = camera;
      groupCamera.clipPlanes.insert(groupCamera.clipPlanes.end(), group.clipPlanes.begin(),
                                    group.clipPlanes.end());
      // The group keeps its decided pixels' planes: the merge compares their depths from the
      // planes, and the compare's fallback tests the triangle along the group's ray (the frame's,
      // or the one its own planes cut: its t then given along the frame's).
      const ScreenEvaluation e = intersectFrameInScreenSpace(
          pass.frame, intersector, groupCamera, threadCount, nullptr, DecidedHits::FromPlanes);
      anyPlanes = anyPlanes || pass.frame.planesById != nullptr;
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
      intersectFrame(pass.frame, intersector, camera, threadCount);
      if (path == AnalyticPath::Auto && firstReason.empty()) {
        firstReason = fewPixelsReason(intersector.triangleCount(), frame.pixelCount());
      }
    }
    pass.mapping = DepthMapping{camera.mode, group.range, false};
    pass.offsets = offsetsOf(pass.part, group, pass.mapping, camera, frame.viewport);
  }
  frame.hits =
      keptHits(frame, passes, camera, nearerIsGreater(camera.mode, scene.depthRange), threadCount);
  frame.planesById =
      anyPlanes ? planesByWholeSceneId(passes, wholeScene.primitiveIdCount()) : nullptr;
  if (evaluated.used) return evaluated;
  ScreenEvaluation rays;
  if (path != AnalyticPath::Rays) {
    rays.reason = "objects with draw state of their own (" + std::to_string(groups.size()) +
                  " groups), none on the screen path: " + firstReason;
  }
  return rays;
}

}  // namespace clipray::engine

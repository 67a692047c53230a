#include "clipray/engine/ReconcileRun.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "clipray/engine/AppPickHits.hpp"
#include "clipray/engine/DrawStateGroups.hpp"
#include "clipray/engine/OffsetRecords.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/util/PhaseClock.hpp"

namespace clipray::engine {

glm::dvec3 nearPlaneCentre(const glm::dmat4& clipFromWorld, DepthMode mode) {
  const glm::dmat4 worldFromClip = glm::inverse(clipFromWorld);
  const glm::dvec4 p = worldFromClip * glm::dvec4(0.0, 0.0, mode.nearNdcZ(), 1.0);
  const glm::dvec3 centre = glm::dvec3(p) / p.w;
  if (p.w > 0.0 && std::isfinite(centre.x + centre.y + centre.z)) return centre;
  // A matrix drawn under conventions that put its near plane behind the eye or at infinity: fall
  // back to the eye (perspective) or the world origin, so both passes still measure from a point.
  const glm::dvec4 e = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
  const glm::dvec3 eye = glm::dvec3(e) / e.w;
  return std::isfinite(eye.x + eye.y + eye.z) ? eye : glm::dvec3(0.0);
}

double depthClampReach(const Scene& scene, const glm::dmat4& clipFromWorld, DepthMode mode) {
  if (!scene.depthClamp || glm::dvec3(matrixRow(clipFromWorld, 3)) != glm::dvec3(0.0)) return 0.0;
  // A parallel camera's ray starts at a near-plane point p0 inside the near quad; a vertex v it
  // can reach behind p0 lies within |v - p0| <= |v - c| + |c - p0| of it (c the quad's centre).
  const glm::dmat4 worldFromClip = glm::inverse(clipFromWorld);
  const glm::dvec3 centre = nearPlaneCentre(clipFromWorld, mode);
  double corner = 0.0;
  for (const double x : {-1.0, 1.0}) {
    for (const double y : {-1.0, 1.0}) {
      const glm::dvec4 p = worldFromClip * glm::dvec4(x, y, mode.nearNdcZ(), 1.0);
      corner = std::max(corner, glm::length(glm::dvec3(p) / p.w - centre));
    }
  }
  double vertex = 0.0;
  for (const MeshObject& object : scene.objects) {
    for (const glm::dvec3& v : object.worldPositions) {
      vertex = std::max(vertex, glm::length(v - centre));
    }
  }
  // A margin so that a vertex at exactly that distance is not the ray's origin (t > 0).
  return (vertex + corner) * 1.0625 + 1.0;
}

namespace {

AnalyticPass analyticPass(const Scene& scene, const Camera& camera, DepthMode mode,
                          Viewport viewport, const PickRayFunction* rayFunction,
                          const PickHitFunction* hitFunction, unsigned threadCount) {
  AnalyticPass pass;
  pass.scene = &scene;
  pass.cameraName = camera.name;
  pass.logDepth = logDepthMapping(camera, mode);
  pass.drawnCamera.clipFromWorld = camera.clipFromWorld(mode, viewport);
  pass.drawnCamera.mode = mode;
  pass.drawnCamera.viewport = viewport;
  pass.drawnCamera.clipPlanes = camera.clipPlanes;
  pass.drawnCamera.depthClamp = scene.depthClamp;
  pass.drawnCamera.depthClampReach =
      depthClampReach(scene, pass.drawnCamera.clipFromWorld, pass.drawnCamera.mode);
  pass.camera.clipFromWorld = lowerLeftClipFromWorld(pass.drawnCamera.clipFromWorld, mode.origin);
  pass.camera.mode = mode.lowerLeft();
  pass.camera.viewport = viewport;
  pass.camera.clipPlanes = camera.clipPlanes;
  pass.camera.depthClamp = pass.drawnCamera.depthClamp;
  pass.drawnCamera.depthClampBeyondFar = clampedFarIsDrawn(mode, scene.depthRange);
  pass.camera.depthClampBeyondFar = pass.drawnCamera.depthClampBeyondFar;
  pass.camera.depthClampReach = pass.drawnCamera.depthClampReach;
  pass.reference = nearPlaneCentre(pass.camera.clipFromWorld, pass.camera.mode);

  if (hitFunction) {
    // The app's picking with its own hits: its rays and hits are the ray side, nothing is traced.
    const PhaseClock raysClock;
    pass.intersector = std::make_unique<SceneIntersector>(
        scene, pass.reference, SceneIntersector::BvhBuild::WhenFirstNeeded,
        pass.drawnCamera.clipFromWorld);
    takeAppPickHits(pass, *hitFunction, threadCount);
    pass.raysMilliseconds = raysClock.wallMilliseconds();
    pass.raysCpuMilliseconds = raysClock.cpuMilliseconds();
    return pass;
  }
  const PhaseClock raysClock;
  // An app's ray function is asked once per pixel and its rays stored; clipray's own rays are
  // computed where the intersection and the compare use them (their cost lands in those two
  // timings; rays then only times setting up the generator).
  pass.frame = rayFunction ? generateRays(pass.drawnCamera, *rayFunction, threadCount)
                           : robustRayFrame(pass.camera);
  pass.raysMilliseconds = raysClock.wallMilliseconds();
  pass.raysCpuMilliseconds = raysClock.cpuMilliseconds();

  const PhaseClock intersectClock;
  // The BVH only when a tile of rays needs it: camera rays traced from screen-space bins never do.
  // Face culling is decided by the matrix as drawn (its clip origin does not change facing).
  pass.intersector = std::make_unique<SceneIntersector>(scene, pass.reference,
                                                        SceneIntersector::BvhBuild::WhenFirstNeeded,
                                                        pass.drawnCamera.clipFromWorld);
  pass.screen = intersectByDrawState(pass.frame, *pass.intersector, scene,
                                     pass.drawnCamera.clipFromWorld, pass.camera, threadCount);
  pass.intersectMilliseconds = intersectClock.wallMilliseconds();
  pass.intersectCpuMilliseconds = intersectClock.cpuMilliseconds();
  return pass;
}

}  // namespace

AnalyticPass runAnalyticPass(const Scene& scene, const Camera& camera, DepthMode mode,
                             Viewport viewport, unsigned threadCount) {
  return analyticPass(scene, camera, mode, viewport, nullptr, nullptr, threadCount);
}

AnalyticPass runAnalyticPass(const Scene& scene, const Camera& camera, DepthMode mode,
                             Viewport viewport, const PickRayFunction& rayFunction,
                             unsigned threadCount) {
  return analyticPass(scene, camera, mode, viewport, &rayFunction, nullptr, threadCount);
}

AnalyticPass runAnalyticPass(const Scene& scene, const Camera& camera, DepthMode mode,
                             Viewport viewport, const PickHitFunction& hitFunction,
                             unsigned threadCount) {
  return analyticPass(scene, camera, mode, viewport, nullptr, &hitFunction, threadCount);
}

RunRecord rasterAndCompare(gl::Renderer& renderer, const AnalyticPass& pass,
                           DepthFormat depthFormat, VertexMode vertexMode, bool images,
                           unsigned threadCount) {
  ComparedRun compared =
      rasterAndComparePixels(renderer, pass, depthFormat, vertexMode, threadCount);
  if (images) encodeRunImages(compared.run, compared.pixels);
  return std::move(compared.run);
}

gl::RenderRequest renderRequest(const AnalyticPass& pass, DepthFormat depthFormat,
                                VertexMode vertexMode) {
  gl::RenderRequest request;
  request.scene = pass.scene;
  request.clipFromWorld = pass.drawnCamera.clipFromWorld;
  request.mode = pass.drawnCamera.mode;
  request.depthFormat = depthFormat;
  request.vertexMode = vertexMode;
  request.vertexReference = pass.reference;
  request.viewport = pass.drawnCamera.viewport;
  request.depthRange = pass.scene->depthRange;
  request.clipPlanes = pass.drawnCamera.clipPlanes;
  request.depthClamp = pass.scene->depthClamp;
  request.logDepth = pass.logDepth;
  return request;
}

ComparedRun rasterAndComparePixels(gl::Renderer& renderer, const AnalyticPass& pass,
                                   DepthFormat depthFormat, VertexMode vertexMode,
                                   unsigned threadCount) {
  gl::RenderTimings renderTimings;
  const RasterFrame raster =
      renderer.render(renderRequest(pass, depthFormat, vertexMode), &renderTimings);
  return compareRasterFrame(pass, raster, depthFormat, vertexMode, renderer.info().subpixelBits,
                            renderTimings, threadCount);
}

ComparedRun compareRasterFrame(const AnalyticPass& pass, const RasterFrame& raster,
                               DepthFormat depthFormat, VertexMode vertexMode, int subpixelBits,
                               const gl::RenderTimings& renderTimings, unsigned threadCount) {
  RasterSetup setup;
  setup.clipFromWorld = pass.camera.clipFromWorld;
  setup.mode = pass.camera.mode;
  setup.depthFormat = depthFormat;
  setup.vertexMode = vertexMode;
  setup.vertexReference = pass.reference;
  setup.subpixelBits = subpixelBits;
  setup.depthRange = pass.scene->depthRange;
  setup.objectDepthRanges = PrimitiveDepthRanges(*pass.scene);
  setup.objectClipPlanes = PrimitiveClipPlanes(*pass.scene);
  setup.objectOffsets = PrimitiveOffsets(*pass.scene);
  setup.clipPlanes = pass.camera.clipPlanes;
  setup.depthClamp = depthClampRays(pass.camera);
  setup.logDepth = pass.logDepth;
  const PhaseClock compareClock;
  // The last run's model where only the depth format differs (its polygons serve every format),
  // else one built for this raster (the old one released first).
  std::unique_ptr<ToleranceModel>& model = pass.toleranceModel;
  if (!model || model->setup().vertexMode != vertexMode ||
      model->setup().subpixelBits != subpixelBits || model->viewport() != raster.viewport) {
    model.reset();
    model = toleranceModelOfRaster(raster, *pass.intersector, setup, threadCount);
  }
  model->useDepthFormat(depthFormat);
  ComparisonResult comparison =
      compareFrames(raster, pass.frame, *pass.intersector, setup, *model, threadCount);
  // Where the unexplained pixels are: part of comparing, and only an inconsistent run has any.
  MismatchClusters clusters;
  if (!comparison.metrics.consistent()) {
    clusters = findMismatchClusters(comparison.pixels.classes, comparison.pixels.viewport,
                                    kReportedClusters);
  }
  const double compareMilliseconds = compareClock.wallMilliseconds();
  const double compareCpuMilliseconds = compareClock.cpuMilliseconds();

  RunRecord run;
  run.scene = pass.scene->name;
  run.camera = pass.cameraName;
  run.convention = pass.drawnCamera.mode;
  run.depthFormat = depthFormat;
  run.vertexMode = vertexMode;
  run.size = pass.camera.viewport;
  run.depthRange = pass.scene->depthRange;
  run.depthClamp = pass.scene->depthClamp;
  run.metrics = comparison.metrics;
  run.polygonOffsets = offsetRecords(*pass.scene, raster, pass.frame, comparison.pixels, *model);
  run.clusters = std::move(clusters);
  if (pass.screen.used) {
    const ScreenEvaluation& s = pass.screen;
    run.screenPath = ScreenPathRecord{static_cast<std::int64_t>(s.background),
                                      static_cast<std::int64_t>(s.decided),
                                      static_cast<std::int64_t>(s.contested),
                                      static_cast<std::int64_t>(s.traced),
                                      static_cast<std::int64_t>(s.boundMisses),
                                      s.rayDeviationNdc,
                                      comparison.metrics.planePixels.fromPlanes,
                                      comparison.metrics.planePixels.alongRays,
                                      {},
                                      static_cast<std::int64_t>(s.frames),
                                      static_cast<std::int64_t>(s.groups)};
  } else if (!pass.screen.reason.empty()) {
    run.screenPath = ScreenPathRecord{.declined = pass.screen.reason};
  }
  run.timings = {renderTimings.raster, renderTimings.readback, pass.raysMilliseconds,
                 pass.intersectMilliseconds, compareMilliseconds};
  run.cpu = {renderTimings.rasterCpu, renderTimings.readbackCpu, pass.raysCpuMilliseconds,
             pass.intersectCpuMilliseconds, compareCpuMilliseconds};
  run.analyticOverRaster = run.timings.analyticOverRaster();
  return {std::move(run), std::move(comparison.pixels)};
}

}  // namespace clipray::engine

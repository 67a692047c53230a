#pragma once
// The steps of one run, below the plan (ReconcileRunner.hpp): the analytic pass of a scene camera
// under one convention (rays and closest hits, shared by the runs of every depth format and vertex
// mode), and a raster frame compared with it. Tests and the picking demo use them directly:
//
//   clipray::gl::Renderer renderer(*context);
//   AnalyticPass rays = runAnalyticPass(scene, scene.cameras[0], kZeroToOne, viewport, myPickRays);
//   RunRecord run = rasterAndCompare(renderer, rays, DepthFormat::Float32, VertexMode::World);
//   EXPECT_TRUE(run.metrics.consistent());
//
// Other projects reconcile through include/clipray/Reconcile.hpp. The ray function is the app's
// own picking code (PickRayFunction); robustPickRays() is clipray's. Every clipFromWorld here is
// column-major, p_clip = clipFromWorld * p_world, built for the DepthMode passed beside it.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clipray/compare/LogarithmicDepth.hpp"
#include "clipray/compare/Reconcile.hpp"
#include "clipray/compare/ScreenEvaluator.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

// Rays and closest hits for one camera under one convention; independent of the depth format
// and vertex mode, so one pass serves every raster variant.
struct AnalyticPass {
  const Scene* scene = nullptr;
  std::string cameraName;
  // The camera as the frame is drawn: the matrix the raster side uploads and the clip control it
  // draws under. The app's picking function is asked with it.
  PickingCamera drawnCamera;
  // The same camera as a lower-left clip origin sees the framebuffer (lowerLeftClipFromWorld):
  // what the rays, the screen bins and the tolerance model work with. The same as drawnCamera for
  // a lower-left origin.
  PickingCamera camera;
  glm::dvec3 reference{0.0};  // centre of the near plane: camera-relative origin for both sides
  // The depth the meshes' shader writes in place of the projective one (Camera::logarithmicDepth,
  // turned around under reversed-Z), for the renderer and the compare alike.
  std::optional<LogDepthMapping> logDepth;
  // Behind a pointer: the tolerance model below refers to it, and the pass may move.
  std::unique_ptr<SceneIntersector> intersector;
  AnalyticFrame frame;
  // What the screen path did with the frame (AnalyticChoice.hpp); used is false on the ray path.
  ScreenEvaluation screen;
  // What the app's own picking hits say beyond the pixels (AppPickHits.hpp): one line each.
  std::vector<std::string> pickNotes;
  // The tolerance model of the pass's last compare: the next run reuses it when only the depth
  // format differs (the screen polygons do not depend on it), else it is replaced (one model at
  // a time, as memory was planned). Kept by compareRasterFrame, one compare at a time.
  mutable std::unique_ptr<ToleranceModel> toleranceModel;
  double raysMilliseconds = 0.0;
  double intersectMilliseconds = 0.0;
  // The process's CPU time in each (PhaseClock).
  double raysCpuMilliseconds = 0.0;
  double intersectCpuMilliseconds = 0.0;
};

// With clipray's robust rays.
AnalyticPass runAnalyticPass(const Scene& scene, const Camera& camera, DepthMode mode,
                             Viewport viewport, unsigned threadCount = 0);
// With the caller's own ray function (e.g. the app's picking code).
AnalyticPass runAnalyticPass(const Scene& scene, const Camera& camera, DepthMode mode,
                             Viewport viewport, const PickRayFunction& rayFunction,
                             unsigned threadCount = 0);
// With the caller's picking and its own hits (takeAppPickHits): nothing is traced.
AnalyticPass runAnalyticPass(const Scene& scene, const Camera& camera, DepthMode mode,
                             Viewport viewport, const PickHitFunction& hitFunction,
                             unsigned threadCount = 0);

// What clipray's renderer draws for the pass in that depth format and vertex mode: the drawn
// camera, the scene's depth range.
gl::RenderRequest renderRequest(const AnalyticPass& pass, DepthFormat depthFormat,
                                VertexMode vertexMode);

// Renders the same camera with the renderer and compares. If images is true, the run's PNGs are
// encoded into the record.
RunRecord rasterAndCompare(gl::Renderer& renderer, const AnalyticPass& pass,
                           DepthFormat depthFormat, VertexMode vertexMode, bool images = true,
                           unsigned threadCount = 0);

// The same, keeping the per-pixel comparison instead of encoding it: for callers that decide
// afterwards whether the run's images are wanted, or encode them elsewhere (encodeRunImages,
// ImageEncoder).
struct ComparedRun {
  RunRecord run;
  PixelComparison pixels;
};
ComparedRun rasterAndComparePixels(gl::Renderer& renderer, const AnalyticPass& pass,
                                   DepthFormat depthFormat, VertexMode vertexMode,
                                   unsigned threadCount = 0);

// Compares a raster frame drawn elsewhere (the app's own render function, AppRender.hpp) with the
// pass, as rasterAndComparePixels compares the renderer's: depthFormat and vertexMode say how it
// was drawn, subpixelBits is the rasterizer's GL_SUBPIXEL_BITS.
ComparedRun compareRasterFrame(const AnalyticPass& pass, const RasterFrame& raster,
                               DepthFormat depthFormat, VertexMode vertexMode, int subpixelBits,
                               const gl::RenderTimings& renderTimings, unsigned threadCount = 0);

// The point near the camera that both passes measure coordinates from: the centre of the near
// plane the rasterizer clips at, in world space.
glm::dvec3 nearPlaneCentre(const glm::dmat4& clipFromWorld, DepthMode mode);
// How far behind the near plane a parallel camera's rays start under the scene's depth clamp
// (PickingCamera::depthClampReach): past every vertex of the scene; 0 without depth clamp or for
// a perspective camera (whose rays start at the eye).
double depthClampReach(const Scene& scene, const glm::dmat4& clipFromWorld, DepthMode mode);

}  // namespace clipray::engine

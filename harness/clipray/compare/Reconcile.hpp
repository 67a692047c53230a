#pragma once
// Reconciliation of a raster frame with an analytic frame, pixel for pixel: coverage, id and depth
// compared, ambiguous pixels counted apart, depth errors measured against the predicted tolerance
// (ToleranceModel.hpp; pixel classes and outputs: docs/reconcile.md). The only matrix is
// RasterSetup::clipFromWorld (column-major, p_clip = clipFromWorld * p_world, for setup.mode).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {

// Per-pixel verdict.
enum class PixelClass : std::uint8_t {
  Background,             // neither side hits
  Agree,                  // same primitive, depth within tolerance
  DepthBeyondTolerance,   // same primitive, depth error above the predicted tolerance
  CoverageEdgeAmbiguous,  // one side hits; the pixel centre is within epsilon of the edge
  CoverageUnexplained,
  IdDepthAmbiguous,  // different primitives whose depths are within tolerance (z-fighting)
  IdEdgeAmbiguous,   // different primitives, pixel centre within epsilon of an edge
  IdUnexplained,
  // The surface lies in front of the near plane: drawn by GL_DEPTH_CLAMP at the near end of the
  // depth range, out of reach of a picking ray that starts on the near plane. Both sides show the
  // same primitive at that depth, or two primitives both there (the first drawn shows).
  InFrontOfNear,
};
const char* pixelClassName(PixelClass value);

struct Distribution {
  double max = 0.0;
  double p50 = 0.0;
  double p99 = 0.0;
};

struct RunMetrics {
  std::int64_t pixels = 0;
  std::int64_t rasterHits = 0;
  std::int64_t rayHits = 0;
  struct {
    std::int64_t total = 0, edgeAmbiguous = 0, unexplained = 0;
  } coverageMismatch;
  struct {
    std::int64_t total = 0, depthAmbiguous = 0, edgeAmbiguous = 0, unexplained = 0;
  } idMismatch;
  std::int64_t depthCompared = 0;         // pixels where both sides hit the same primitive
  std::int64_t depthBeyondTolerance = 0;  // of those, error above the predicted tolerance
  // Pixels of class InFrontOfNear (depth clamp; not in depthCompared: both sides store the near
  // end of the depth range, nothing is measured along the ray).
  std::int64_t inFrontOfNear = 0;
  // Pixels the screen path decided from their triangles' planes (AnalyticFrame::planesById):
  // compared from the planes, and compared along their rays (the sides differ, or the planes'
  // reach leaves the class or the depth quantum uncertain).
  struct {
    std::int64_t fromPlanes = 0, alongRays = 0;
  } planePixels;
  Distribution depthErrorQuanta;  // |d_r - d_a| / quantum(d_a)
  Distribution distanceRelError;  // |t_r - t_a| / distance from the eye
  Distribution toleranceRatio;    // |d_r - d_a| / predicted tolerance (p50 unused in report)
  // The same depth figures split by surface kind: "triangle" or an analytic primitive kind
  // (GLSL float rays against CPU double rays). Only kinds with compared pixels are listed.
  struct KindFigures {
    std::string kind;
    std::int64_t depthCompared = 0;
    Distribution depthErrorQuanta, distanceRelError, toleranceRatio;
  };
  std::vector<KindFigures> byKind;
  bool consistent() const {
    return coverageMismatch.unexplained == 0 && idMismatch.unexplained == 0 &&
           depthBeyondTolerance == 0;
  }
};

// Per-pixel data kept for the images. Frame buffers (util/FrameBuffers.hpp): the next run of the
// same size reuses their pages instead of faulting in fresh ones.
struct PixelComparison {
  Viewport viewport;
  FrameVector<float> rasterDepth;     // NaN where the raster shows background
  FrameVector<double> analyticDepth;  // NaN where the ray misses
  FrameVector<float> toleranceRatio;  // NaN where not compared
  FrameVector<PixelClass> classes;
};

struct ComparisonResult {
  RunMetrics metrics;
  PixelComparison pixels;
};

// What compareFrames calls a pixel whose two sides name different primitives (0: background) at
// window position `centre`: the ray side hit rayId at window depth rayDepth, whose tolerance is
// rayTolerance (both unused where rayId is 0). Coverage mismatches are edge-ambiguous when the
// pixel centre lies within the hit primitive's edge epsilon; id mismatches are depth-ambiguous
// (z-fighting) when the raster's primitive lies along the pixel within the summed tolerances of
// the ray's depth, else edge-ambiguous near either primitive's edge; anything else unexplained.
PixelClass classifyMismatch(const ToleranceModel& model, std::uint32_t rayId, double rayDepth,
                            double rayTolerance, std::uint32_t rasterId, glm::dvec2 centre);

// Compares the frames. The intersector supplies the triangles both sides drew.
ComparisonResult compareFrames(const RasterFrame& raster, const AnalyticFrame& analytic,
                               const SceneIntersector& intersector, const RasterSetup& setup,
                               unsigned threadCount = 0);
// The tolerance model compareFrames builds for a raster frame: the screen polygons of the
// primitives the raster shows, clipped up front across threadCount threads.
std::unique_ptr<ToleranceModel> toleranceModelOfRaster(const RasterFrame& raster,
                                                       const SceneIntersector& intersector,
                                                       const RasterSetup& setup,
                                                       unsigned threadCount = 0);
// The same comparison with a model built before, for this setup (another raster of the same
// camera, convention and vertex mode, told this depth format: ToleranceModel::useDepthFormat).
// A model for another setup is a bug (InternalError).
ComparisonResult compareFrames(const RasterFrame& raster, const AnalyticFrame& analytic,
                               const SceneIntersector& intersector, const RasterSetup& setup,
                               const ToleranceModel& model, unsigned threadCount = 0);

}  // namespace clipray

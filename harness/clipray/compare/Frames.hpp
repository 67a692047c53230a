#pragma once
// The two sides of a reconcile, pixel for pixel (the raster's depth and ids, the rays' hits), and
// the row-parallel loops that fill and compare them. Row 0 is the bottom row (GL's lower-left
// origin). PickingCamera::clipFromWorld: column-major, p_clip = clipFromWorld * p_world, for its
// mode.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <new>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/Picking.hpp"
#include "clipray/Ray.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/FrameBuffers.hpp"

namespace clipray {

// What the GL raster pass read back: window depth (GL_FLOAT) and primitive id (0 = background).
struct RasterFrame {
  Viewport viewport;
  std::vector<float> depth;
  std::vector<std::uint32_t> ids;
};

// A triangle's NDC depth z and reciprocal clip w where the line of sight through the pixel centre
// at NDC (x, y) crosses it, as planes over (x, y): z = za x + (zb y + zc), likewise r = 1 / w,
// each with a bound on its distance from the exact crossing's (ScreenTriangleSetup.hpp).
struct TrianglePlanes {
  double za = 0.0, zb = 0.0, zc = 0.0, depthError = 0.0;
  double ra = 0.0, rb = 0.0, rc = 0.0, reciprocalWError = 0.0;
};

// What the analytic pass found: the ray of each pixel and its closest hit.
struct AnalyticFrame {
  Viewport viewport;
  // The rays, one per pixel (resize() leaves them unwritten: every pass writes every ray); or
  // none stored, and pixelCentreRays computes them where a pass needs them (robustRayFrame).
  // Never both: the passes refuse a frame that has both, or neither for each pixel.
  FrameVector<Ray> rays;
  std::shared_ptr<const PixelCentreRays> pixelCentreRays;
  FrameVector<Hit> hits;
  // Where the screen path decided a pixel's triangle from its planes alone (ScreenEvaluator.hpp,
  // DecidedHits::FromPlanes), the hit holds the triangle's id and t = NaN: no ray was traced
  // there, and the compare evaluates planesById[id] at the pixel centre instead (empty: none).
  // Only the decided triangles' entries are written.
  std::shared_ptr<const FrameVector<TrianglePlanes>> planesById;

  std::size_t pixelCount() const {
    return static_cast<std::size_t>(viewport.width) * static_cast<std::size_t>(viewport.height);
  }
  // Whether the frame has a ray for each pixel: stored, or computed for this viewport.
  bool hasRays() const {
    return pixelCentreRays ? rays.empty() && pixelCentreRays->viewport() == viewport
                           : rays.size() == pixelCount();
  }
};

// The rays a camera's depth clamp needs (RobustRays.hpp).
inline DepthClampRays depthClampRays(const PickingCamera& camera) {
  return {camera.depthClamp, camera.depthClampReach, camera.depthClampBeyondFar};
}

// A pixel whose ray function returned nullopt holds this ray: tMax < 0 never hits anything.

// Pass 1: one ray per pixel from the ray function, multi-threaded over rows (frame.hits empty).
AnalyticFrame generateRays(const PickingCamera& camera, const PickRayFunction& rayFunction,
                           unsigned threadCount = 0);
// The same with clipray's robust rays, called directly (no per-pixel std::function dispatch).
AnalyticFrame generateRobustRays(const PickingCamera& camera, unsigned threadCount = 0);
// A frame with the same rays, bit for bit, that stores none: intersectFrame and compareFrames
// compute each tile's or row's rays where they use them (what a reconcile runs).
AnalyticFrame robustRayFrame(const PickingCamera& camera);
// Pass 2: the closest hit of every ray, multi-threaded over rows: 8x8 tiles traced as SIMD
// packets walking the BVH.
void intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                    unsigned threadCount = 0);
// The same hits, bit for bit, faster for a camera's pixel-centre rays: the triangles are binned
// in screen space once for the camera (FrameBins) and each tile whose rays stay on their pixels'
// lines of sight tests its bins instead of walking the BVH (other tiles walk it). Returns how many
// tiles used the bins.
std::size_t intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                           const PickingCamera& camera, unsigned threadCount = 0);

// Runs body(rowBegin, rowEnd) over [0, rows) split into chunks across threadCount threads
// (0: hardware concurrency).
void parallelForRows(int rows, unsigned threadCount, const std::function<void(int, int)>& body);
// How many workers parallelForRowsByWorker runs for these arguments.
unsigned parallelWorkerCount(int rows, unsigned threadCount);
// parallelForRows that also tells body which worker (0 .. parallelWorkerCount - 1) runs the
// chunk: a worker runs its chunks one after the other, so per-worker state needs no lock.
void parallelForRowsByWorker(int rows, unsigned threadCount,
                             const std::function<void(unsigned worker, int, int)>& body);

}  // namespace clipray

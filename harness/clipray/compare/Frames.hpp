#pragma once
// The two sides of a reconcile, pixel for pixel. Row 0 is the bottom row (GL's lower-left origin).

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/math/Conventions.hpp"
#include "clipray/rays/Ray.hpp"

namespace clipray {

// What the GL raster pass read back: window depth (GL_FLOAT) and primitive id (0 = background).
struct RasterFrame {
  Viewport viewport;
  std::vector<float> depth;
  std::vector<std::uint32_t> ids;
};

// What the analytic pass found: the ray of each pixel and its closest hit.
struct AnalyticFrame {
  Viewport viewport;
  std::vector<Ray> rays;
  std::vector<Hit> hits;
};

// The camera a ray function is asked about: the matrix the app drew with, the conventions it
// drew under and the framebuffer size.
struct PickingCamera {
  glm::dmat4 clipFromWorld{1.0};
  DepthMode mode;
  Viewport viewport;
};

// A ray for pixel (x, y) (lower-left origin, integer pixel indices) or nullopt for "no ray".
// This is how an app plugs its own picking code into a reconcile.
using PickRayFunction = std::function<std::optional<Ray>(int x, int y, const PickingCamera&)>;

// The project's own picking rays: RobustRayGenerator through each pixel centre.
PickRayFunction robustPickRays();

// A pixel whose ray function returned nullopt holds this ray: tMax < 0 never hits anything.

// Pass 1: one ray per pixel from the ray function, multi-threaded over rows (frame.hits empty).
AnalyticFrame generateRays(const PickingCamera& camera, const PickRayFunction& rayFunction,
                           unsigned threadCount = 0);
// The same with clipray's robust rays, called directly (no per-pixel std::function dispatch).
AnalyticFrame generateRobustRays(const PickingCamera& camera, unsigned threadCount = 0);
// Pass 2: the closest hit of every ray, multi-threaded over rows.
void intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                    unsigned threadCount = 0);

// Runs body(rowBegin, rowEnd) over [0, rows) split into chunks across threadCount threads
// (0: hardware concurrency).
void parallelForRows(int rows, unsigned threadCount, const std::function<void(int, int)>& body);

}  // namespace clipray

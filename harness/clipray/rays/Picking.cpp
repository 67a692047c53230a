// pickingInWindow: clipray's lower-left integer pixels in an app's window coordinates, and the
// app's ray normalized and ended at the far clip plane (Picking.hpp).

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "clipray/InputError.hpp"
#include "clipray/Picking.hpp"

namespace clipray {

namespace {

int framebufferHeightOf(const AppWindow& window, Viewport viewport) {
  return window.framebufferHeight != 0 ? window.framebufferHeight
                                       : window.viewportY + viewport.height;
}

void validateWindow(const AppWindow& window) {
  if (!(std::isfinite(window.pixelRatio) && window.pixelRatio > 0.0)) {
    std::ostringstream got;
    got << window.pixelRatio;
    throw InputError("AppWindow: pixelRatio: expected a positive number, got " + got.str());
  }
  if (window.viewportX < 0 || window.viewportY < 0) {
    throw InputError("AppWindow: viewport offset: expected non-negative x and y, got (" +
                     std::to_string(window.viewportX) + ", " + std::to_string(window.viewportY) +
                     ")");
  }
  if (window.framebufferWidth < 0 || window.framebufferHeight < 0) {
    throw InputError(
        "AppWindow: framebuffer size: expected 0 (the viewport's edge) or a size in "
        "pixels, got " +
        std::to_string(window.framebufferWidth) + "x" + std::to_string(window.framebufferHeight));
  }
}

// Where the ray leaves the view volume through the far clip plane. Inside that plane a
// homogeneous world point p satisfies f . p >= 0, with f = row3 - row2 (z <= w) for a classic
// depth range and f = row2 - z_n row3 (z >= z_n w) for reversed-Z; f . (o + t d) is linear in t.
double farPlaneDistance(const Ray& ray, const PickingCamera& camera) {
  const glm::dmat4 m = glm::transpose(camera.clipFromWorld);  // m[i]: row i of clipFromWorld
  const glm::dvec4 far =
      camera.mode.reversed ? m[2] - camera.mode.clipVolumeMinZ() * m[3] : m[3] - m[2];
  const double atOrigin = glm::dot(far, glm::dvec4(ray.origin, 1.0));
  const double rate = glm::dot(far, glm::dvec4(ray.direction, 0.0));
  if (!(rate < 0.0)) return std::numeric_limits<double>::infinity();
  const double t = -atOrigin / rate;
  return t > 0.0 ? t : 0.0;
}

}  // namespace

glm::dvec2 windowPositionOfPixel(const AppWindow& window, int x, int y, Viewport viewport) {
  return windowPositionOfPoint(window, glm::dvec2(x + 0.5, y + 0.5), viewport);
}

glm::dvec2 windowPositionOfPoint(const AppWindow& window, glm::dvec2 point, Viewport viewport) {
  const double framebufferX = window.viewportX + point.x;
  const double framebufferY = window.viewportY + point.y;  // from the bottom
  const double windowY = window.origin == WindowOrigin::LowerLeft
                             ? framebufferY
                             : framebufferHeightOf(window, viewport) - framebufferY;
  return {framebufferX / window.pixelRatio, windowY / window.pixelRatio};
}

namespace {

void requireViewportInWindow(const AppWindow& window, Viewport viewport) {
  if (framebufferHeightOf(window, viewport) < window.viewportY + viewport.height) {
    throw InputError("AppWindow: framebufferHeight: " + std::to_string(window.framebufferHeight) +
                     " pixels cannot hold a viewport of height " + std::to_string(viewport.height) +
                     " at y " + std::to_string(window.viewportY));
  }
}

// The app's ray with a unit direction, ended at the far clip plane where its tMax is 0; returns
// the direction's length it had (0 where it has no usable direction: the ray is left as it was).
double normalizeAppRay(Ray& ray, const PickingCamera& camera) {
  const double length = glm::length(ray.direction);
  if (!(length > 0.0 && std::isfinite(length))) return 0.0;
  const bool toFarPlane = ray.tMax == 0.0;
  ray.direction /= length;
  ray.tMax = toFarPlane ? farPlaneDistance(ray, camera) : ray.tMax * length;
  return length;
}

// Where the app is asked for pixel (x, y), and the camera it is asked with: the pixel centre and
// the run's camera, or in a multisampled run the sample's position with the drawn matrix (the
// sheared one would move the app's ray twice).
struct AppQuery {
  glm::dvec2 window;
  PickingCamera camera;
};
AppQuery appQuery(const AppWindow& window, int x, int y, const PickingCamera& camera) {
  if (!camera.samplePosition) {
    return {windowPositionOfPixel(window, x, y, camera.viewport), camera};
  }
  AppQuery query{
      windowPositionOfPoint(window, glm::dvec2(x, y) + *camera.samplePosition, camera.viewport),
      camera};
  query.camera.clipFromWorld = camera.drawnClipFromWorld;
  query.camera.samplePosition.reset();
  return query;
}

}  // namespace

PickRayFunction pickingInWindow(const AppWindow& window, AppPickFunction pick) {
  validateWindow(window);
  return [window, pick = std::move(pick)](int x, int y,
                                          const PickingCamera& camera) -> std::optional<Ray> {
    requireViewportInWindow(window, camera.viewport);
    const AppQuery query = appQuery(window, x, y, camera);
    std::optional<Ray> ray = pick(query.window, query.camera);
    if (!ray || normalizeAppRay(*ray, camera) == 0.0) return std::nullopt;
    return ray;
  };
}

PickHitFunction pickHitsInWindow(const AppWindow& window, AppPickHitFunction pick) {
  validateWindow(window);
  return [window, pick = std::move(pick)](int x, int y,
                                          const PickingCamera& camera) -> std::optional<PickHit> {
    requireViewportInWindow(window, camera.viewport);
    const AppQuery query = appQuery(window, x, y, camera);
    std::optional<PickHit> hit = pick(query.window, query.camera);
    if (!hit) return std::nullopt;
    const double length = normalizeAppRay(hit->ray, camera);
    if (length == 0.0) return std::nullopt;
    hit->t *= length;
    return hit;
  };
}

}  // namespace clipray

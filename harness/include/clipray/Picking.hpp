#pragma once
// How an app's picking code plugs into a reconcile. clipray asks for the ray of each pixel of the
// viewport it compares, (x, y) with integer indices from GL's lower-left corner; an app thinks in
// mouse positions in its own window (upper-left origin, HiDPI scale, a viewport that may not start
// at the window's corner). pickingInWindow() translates one into the other, so a test calls the
// app's function exactly as the app's mouse handler does. PickingCamera::clipFromWorld is
// column-major, p_clip = clipFromWorld * p_world, built for PickingCamera::mode.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/InputError.hpp"
#include "clipray/Ray.hpp"

namespace clipray {

// The camera a ray function is asked about: the matrix the app drew with, the conventions it
// drew under and the viewport's size in framebuffer pixels.
struct PickingCamera {
  glm::dmat4 clipFromWorld{1.0};
  DepthMode mode;
  Viewport viewport;
  // The user clip planes it draws with (world space, gl_ClipDistance = dot(plane, (p, 1)), kept
  // where >= 0); a ray function whose picking should not reach what they clip cuts its rays.
  std::vector<glm::dvec4> clipPlanes{};
  // GL_DEPTH_CLAMP (Scene::depthClamp): nothing is clipped at the near and far planes, and what
  // lies in front of the near plane is drawn at the depth range's near end. A ray function that
  // should reach it starts its rays at the eye (perspective) or depthClampReach behind the near
  // plane (parallel: as far as the scene reaches behind it), with no far end.
  bool depthClamp = false;
  double depthClampReach = 0.0;
  // What lies beyond the far plane is drawn too (at the far end of the depth range), unless that
  // end is the depth buffer's clear value, which a strict depth test never passes: rays then end
  // at the far plane.
  bool depthClampBeyondFar = false;
  // A multisampled run (ReconcileOptions::samples) asks for the ray through one sample of the
  // pixel instead of its centre. samplePosition is where that sample lies in the pixel (pixels
  // from its lower-left corner, framebuffer orientation, as glGetMultisamplefv reports it), and
  // clipFromWorld is then the drawn matrix sheared to carry that position onto the pixel centre:
  // a function that builds the centre's ray from clipFromWorld gets the sample's. The drawn matrix
  // itself is drawnClipFromWorld. pickingInWindow and pickHitsInWindow ask the app at the sample's
  // own window position with the drawn matrix, so an app's picking in window coordinates needs
  // nothing of this.
  std::optional<glm::dvec2> samplePosition{};
  glm::dmat4 drawnClipFromWorld{1.0};
};

// A ray for pixel (x, y) (lower-left origin, integer pixel indices) or nullopt for "no ray": the
// ray must start where the rasterizer's near clip plane crosses the pixel's line of sight, point
// into the view volume (unit direction) and end at tMax.
using PickRayFunction = std::function<std::optional<Ray>(int x, int y, const PickingCamera&)>;

// The project's own picking rays: RobustRayGenerator through each pixel centre.
PickRayFunction robustPickRays();

// What an app's own picking found under a pixel: its ray and what its intersection code hit along
// it, so that the code itself is tested (its culling policy included), not only the ray.
struct PickHit {
  Ray ray;  // as a PickRayFunction returns it (normalized by clipray)
  // The mesh it hit, in the order the scene added them (AppFrame::firstIds' order); nullopt: it
  // hit nothing.
  std::optional<std::size_t> mesh;
  // The triangle of that mesh (its index order); nullopt: clipray takes the mesh's triangle that
  // the ray meets nearest to t (a scan of the mesh: slow for big meshes).
  std::optional<std::uint32_t> triangle;
  double t = 0.0;  // how far along the ray (in units of its direction's length) it hit
};
// The app's pick at pixel (x, y) (lower-left origin, integer pixel indices), or nullopt for "no
// ray".
using PickHitFunction = std::function<std::optional<PickHit>(int x, int y, const PickingCamera&)>;

// The app's window, as its mouse handler sees it.
struct AppWindow {
  WindowOrigin origin = WindowOrigin::UpperLeft;  // where the app's mouse y counts from
  double pixelRatio = 1.0;  // framebuffer pixels per window unit (2 on a typical HiDPI screen)
  // glViewport's x and y: the viewport's lower-left corner in framebuffer pixels.
  int viewportX = 0;
  int viewportY = 0;
  // The framebuffer's size in pixels; 0: the viewport's offset plus its size (a viewport that
  // reaches the window's right and top edges). Picking needs the height only with an upper-left
  // origin; an app render function (Reconcile.hpp) draws into a framebuffer of this size.
  int framebufferWidth = 0;
  int framebufferHeight = 0;
};

// The app's picking function in its own terms: the ray under the mouse at `window` (window units,
// x to the right, y from AppWindow::origin). Direction need not be unit length. tMax 0 (Ray's
// default) means "to the far plane": the adapter ends the ray where it leaves the view volume
// through the far clip plane (never, with an infinite far plane).
using AppPickFunction = std::function<std::optional<Ray>(glm::dvec2 window, const PickingCamera&)>;

// The centre of viewport pixel (x, y) (lower-left origin) in the app's window coordinates.
glm::dvec2 windowPositionOfPixel(const AppWindow& window, int x, int y, Viewport viewport);
// A point of the viewport (lower-left origin, pixels: pixel (x, y)'s centre is (x + 0.5, y + 0.5))
// in the app's window coordinates.
glm::dvec2 windowPositionOfPoint(const AppWindow& window, glm::dvec2 point, Viewport viewport);

// A PickRayFunction that calls `pick` at each pixel centre's window position (each sample's, in a
// multisampled run: PickingCamera::samplePosition) and normalizes the ray it returns. Throws
// InputError for a window that cannot hold the viewport (pixelRatio not positive and finite,
// framebufferHeight below viewportY + the viewport's height).
PickRayFunction pickingInWindow(const AppWindow& window, AppPickFunction pick);

// The app's picking with its own hits, in its own terms: what it hit under the mouse at `window`
// (as AppPickFunction), its ray's tMax 0 meaning "to the far plane".
using AppPickHitFunction =
    std::function<std::optional<PickHit>(glm::dvec2 window, const PickingCamera&)>;
// A PickHitFunction that calls `pick` at each pixel centre's window position, normalizes its
// ray as pickingInWindow does and scales its t to the unit direction. Throws InputError as
// pickingInWindow does.
PickHitFunction pickHitsInWindow(const AppWindow& window, AppPickHitFunction pick);

}  // namespace clipray

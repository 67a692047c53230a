#pragma once
// The closest triangle of every pixel decided in screen space, as a rasterizer decides it, with a
// bound on every decision that makes it the ray path's decision (intersectFrame with the camera's
// robust rays, RobustRays.hpp): a pixel the bounds decide is the hit the ray path finds, bit for
// bit; a pixel they cannot decide is traced by the ray path. PickingCamera::clipFromWorld:
// column-major, p_clip = clipFromWorld * p_world, a lower-left origin's, built for its mode.
//
// Per triangle, the three edge functions of homogeneous rasterization (Olano and Greer 1997:
// E_k(s) = det[h_j, h_l, s] over the vertices' clip (x, y, w) and the pixel centre's NDC
// s = (x, y, 1), positive inside where det[h0, h1, h2] is) and the NDC depth plane
// z(s) = sum_k E_k(s) z_k / det, in double. A pixel centre whose every edge function exceeds its
// margin is inside the projection of the triangle's part in front of the eye, and every ray that
// stays within Delta of the centre (the ray path's rays do: ScreenTriangleSetup.cpp bounds their
// deviation from the camera's matrices) crosses the triangle; one below minus its margin is
// outside, and no such ray meets it. The nearest of the triangles a pixel's ray crosses is decided
// on the depth plane with the same margins. Where two triangles lie within them of each other,
// their watertight tests decide; pixels where a margin is not cleared are the ray path's.

#include <cstddef>
#include <string>

#include "clipray/Picking.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/SceneIntersector.hpp"

namespace clipray {

// What the evaluator did with a frame's pixels.
struct ScreenEvaluation {
  // Whether the frame was evaluated in screen space; else `reason` says why not, and the frame's
  // hits are the ray path's (intersectFrame with the camera).
  bool used = false;
  std::string reason;
  std::size_t background = 0;  // no triangle can be hit: no ray computed
  std::size_t decided = 0;     // one triangle is the nearest: its test gives t, or its planes
  std::size_t contested = 0;   // several triangles within the depth margin: each tested
  std::size_t traced = 0;      // a margin not cleared: the ray path's full search
  // Decided or contested pixels whose tested triangles all missed (a bound that did not hold):
  // traced too. Zero unless a bound is wrong; the tests hold it at zero (DecidedHits::Tested
  // tests every decided pixel; FromPlanes the contested ones only).
  std::size_t boundMisses = 0;
  // The bound on how far the ray path's rays stray from their pixel centres, in NDC.
  double rayDeviationNdc = 0.0;
  // How many frames of the viewport's pixels the counts cover: 1, or where objects are drawn in
  // `groups` of their own state (engine/DrawStateGroups.hpp), each group's frame the screen path
  // evaluated, summed (the deviation their largest).
  std::size_t frames = 1;
  std::size_t groups = 1;
};

// Where a pixel is decided (one triangle the nearest), that triangle's NDC depth at the pixel
// centre from its depth plane, and the bound on its distance from the depth where the exact line
// of sight through the centre crosses the triangle (ScreenTriangleSetup.hpp's depthError); NaN at
// every other pixel. What a compare in screen space takes instead of a ray and its t.
struct ScreenDepths {
  FrameVector<double> ndcZ;
  FrameVector<double> bound;
};

// What a pixel whose nearest triangle the planes decide gets in frame.hits.
enum class DecidedHits {
  // That triangle's watertight test along the pixel's ray: the ray path's hit, bit for bit.
  Tested,
  // The triangle's id and t = NaN, no ray computed (frame.planesById holds its planes, which the
  // compare evaluates at the pixel centre instead). Pixels whose ray might not exist (a line of
  // sight at the horizon of an oblique near plane) are tested all the same.
  FromPlanes,
};

// Fills frame.hits for the camera's robust rays (frame from robustRayFrame(camera)) with the same
// hits intersectFrame(frame, intersector, camera) gives, bit for bit (for decided pixels as
// `decided` says). The camera's user clip planes cut the rays as they cut the drawing: a triangle
// a plane may cut is never decided where it may be the nearest (ScreenTriangleSetup.hpp). Analytic
// primitives stay on rays: every pixel of a tile one may cover (FrameBins::primitiveMayCover) is
// traced. Frames outside what the screen decisions cover (primitives alone, depth clamp, stored
// rays, a camera whose rays' deviation has no bound) are traced by the ray path, with the reason.
// Fills depths too where one is given (resized to the frame; all NaN where the frame is not
// evaluated).
ScreenEvaluation intersectFrameInScreenSpace(AnalyticFrame& frame,
                                             const SceneIntersector& intersector,
                                             const PickingCamera& camera, unsigned threadCount = 0,
                                             ScreenDepths* depths = nullptr,
                                             DecidedHits decided = DecidedHits::Tested);

}  // namespace clipray

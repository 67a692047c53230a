#pragma once
// What the screen evaluator (ScreenEvaluator.hpp) decides on (internal to compare/): per frame,
// how far the ray path's robust rays stray from their pixel centres in NDC (Delta) and the terms
// every triangle shares; per triangle, the three edge functions and the NDC depth plane at a pixel
// centre's NDC (x, y), each with the margin beyond which its sign or order is the ray path's.
// PickingCamera::clipFromWorld: column-major, p_clip = clipFromWorld * p_world, lower-left origin.

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Picking.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/rays/RobustRays.hpp"

namespace clipray::screen {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
// How far (in NDC depth) a crossing must lie from the near and the far plane to be decided in or
// out of the ray's interval: far more than the rounding of t against 0 and tMax.
inline constexpr double kRangeMargin = 0x1p-24;
// Two crossings whose NDC depths lie within this fraction of each other are both the ray path's
// to order (the watertight t of each, with its tie rule): far more than the rounding of t.
inline constexpr double kOrderMargin = 0x1p-20;

// Whether a crossing whose depth key may be as low as `low` could tie with or beat the nearest
// surely crossed triangle, whose key is at most nearestHigh.
inline bool mayBeNearest(double low, double nearestHigh) {
  return low <= nearestHigh + kOrderMargin * (nearestHigh < 0.0 ? -nearestHigh : nearestHigh);
}

// What every triangle's setup needs from the frame.
struct FrameTerms {
  glm::dmat4 clipFromRelative{1.0};
  glm::dmat4 absClipFromRelative{1.0};
  glm::dvec4 translationError{0.0};  // of folding the reference into clipFromRelative
  glm::dvec4 rowSize{0.0};           // per clip row, sum_k |m[k][r]|: a world move's clip size
  double delta = 0.0;                // Delta (rayDeviation)
  double nearExtent = 0.0;           // the largest |o - reference| (inf-norm) of a ray origin
  double zNear = 0.0, sigma = 1.0;   // the near plane's NDC z; sigma: the depth's direction
  double keyFar = kInf;              // sigma (z_far - z_near); +inf for an infinite far plane
  // A crossing's lower key above keyNearIn is surely beyond the ray's start, its upper key below
  // keyNearOut surely before it: +-kRangeMargin about the near plane; both -inf under depth clamp,
  // whose rays start at the eye (every crossing a binned ray can reach lies beyond it).
  double keyNearIn = kRangeMargin, keyNearOut = -kRangeMargin;
  // Under depth clamp with a perspective camera, the clip (x, y, w) box that holds every point of
  // every ray with w below eyeBoxW: |x|, |y| <= eyeBoxXY, -eyeBoxBelowW <= w < eyeBoxW (the bins
  // and Delta hold from eyeBoxW on); eyeBoxW 0: no such box.
  double eyeBoxW = 0.0, eyeBoxXY = 0.0, eyeBoxBelowW = 0.0;
  Viewport viewport;
  // The camera's user clip planes folded to the reference (n . p_relative + d'), each with the
  // margin beyond which a vertex's side of it is the cut ray's (clipCutDeviation's comment).
  std::vector<glm::dvec4> clipPlanes;
  std::vector<double> clipMargins;
};

// A triangle's edge functions, depth plane and their margins, for one camera.
struct TriangleSetup {
  // E_k(x, y) = a x + b y + c, edge k opposite vertex k; multiplied by the orientation's sign when
  // it is certain, so that the inside is where every E_k > margin_k.
  double a[3], b[3], c[3];
  double margin[3];
  double sign = 0.0;                     // sign(det) when it is certain; 0: not
  double za = 0.0, zb = 0.0, zc = 0.0;   // NDC depth z(x, y) = za x + zb y + zc
  double depthError = kInf;              // |z - exact z| over the ray's reach: the key's error
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;  // pixels the triangle may matter to (inclusive)
  std::uint32_t primitiveId = 0;
  // A user clip plane may cut it: where a ray crosses it the crossing may be clipped, so it is
  // never surely crossed (a triangle every plane keeps whole is not cut; one a plane clips whole
  // matters to no pixel).
  bool clipped = false;
  // The triangle may meet FrameTerms' eye box (a depth-clamped ray may reach it where neither the
  // bins nor Delta hold): the frame is the ray path's.
  bool nearEye = false;
};

// Where a user clip plane cuts a triangle, over the pixel centre s: the crossing surely kept by it
// where keep(s) = ka x + kb y + kc > keepError, surely clipped where clipAway(s) < -clipAwayError
// (ScreenTriangleSetup.cpp, item 4); used false: no such edges. A triangle has kMaxClipCuts of
// them: one per plane that cuts it, none used when more planes than that do (a section view's
// corner).
inline constexpr int kMaxClipCuts = 2;
struct ClipEdge {
  double ka = 0.0, kb = 0.0, kc = 0.0, keepError = kInf;
  double ca = 0.0, cb = 0.0, cc = 0.0, clipAwayError = kInf;
  bool used = false;
};

// Delta for the generator's rays; nullopt, with the reason, where they have no such bound.
std::optional<double> rayDeviation(const RobustRayGenerator& generator, std::string& reason);

// Under depth clamp (RobustRayGenerator::depthClamp): the rays' Delta, at every crossing of clip
// w at least wLeast for a perspective camera, whose rays start at the eye (their stray from the
// line of sight grows as 1 / w towards it), and the box of FrameTerms::eyeBoxW that holds their
// points below wLeast (eyeBoxW 0 for a parallel camera, whose rays start parallelReach behind the
// near plane and keep one w); nullopt, with the reason, where they have no such bound.
struct DepthClampReach {
  double delta = 0.0;
  double wLeast = 0.0;  // the screen bins' wClip
  double eyeBoxW = 0.0, eyeBoxXY = 0.0, eyeBoxBelowW = 0.0;
};
std::optional<DepthClampReach> depthClampDeviation(const RobustRayGenerator& generator,
                                                   std::string& reason);

// How far, in NDC, the user clip planes' cut moves a ray from its line (the rounding of its new
// origin), at any crossing that lies beyond that origin, for a scene whose vertices lie within
// sceneExtent (inf-norm) of the reference; 0 without planes; nullopt, with the reason, where it
// has no bound. Delta for a camera with clip planes is rayDeviation (under depth clamp,
// depthClampDeviation's, given as clamp) plus this.
std::optional<double> clipCutDeviation(const RobustRayGenerator& generator,
                                       const glm::dvec3& reference, double sceneExtent,
                                       std::string& reason, const DepthClampReach* clamp = nullptr);

// The terms of the camera's frame: clipFromRelative is the screen bins' (FrameBins), reference the
// intersector's, delta from rayDeviation (and clipCutDeviation), sceneExtent as there.
// Under depth clamp, clamp is depthClampDeviation's (its delta the one given).
FrameTerms frameTerms(const PickingCamera& camera, const RobustRayGenerator& generator,
                      const glm::dmat4& clipFromRelative, const glm::dvec3& reference, double delta,
                      double sceneExtent = 0.0, const DepthClampReach* clamp = nullptr);

// The setup of a triangle for the walk; where planes is given, also the triangle's depth plane and
// the plane of 1 / clip w where the line of sight crosses it, r(x, y) = ra x + rb y + rc (the sum
// of the edge functions over |det|, positive in front of the eye), each with its error bound (both
// infinite where the orientation is not certain): what the compare evaluates at decided pixels.
// Where clipEdges is given (kMaxClipCuts of them, each written either way), the edges of the user
// clip planes that cut the triangle.
TriangleSetup setupTriangle(const FrameTerms& frame, const detail::BvhTriangle& triangle,
                            TrianglePlanes* planes = nullptr, ClipEdge* clipEdges = nullptr);

}  // namespace clipray::screen

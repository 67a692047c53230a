// The bounds that make the screen evaluator's decisions the ray path's (ScreenTriangleSetup.hpp).
// Notation: u = 2^-53 (double's unit roundoff), gamma(n) = n u / (1 - n u) the bound on n roundings
// (Higham, "Accuracy and Stability of Numerical Algorithms", 3.1; pbrt-v4's gamma,
// src/pbrt/util/float.h). |M| is the matrix of absolute values, so |M v| <= |M| |v|.
//
// What a pixel's ray does (RobustRays.cpp, Watertight.hpp) and what bounds it:
//   1. The ray strays from the pixel centre's line of sight by at most Delta in NDC at every point
//      along it (rayDeviation below: the near point from worldFromClip, the direction from the
//      plane-cross terms, each bounded from its operations).
//   2. The watertight test decides on the triangle's vertices moved by at most eta (world units)
//      each: the subtraction of the ray origin, the shear and the products of the edge functions
//      each round once per coordinate, and a rounded product's sign is that of the exact product
//      of a coordinate moved by one rounding (the subtraction keeps the sign of its exact result).
//   3. Its t is compared with 0 and tMax: a hit decided on depth needs the crossing to be clear of
//      the near and far planes (kRangeMargin), and of another triangle's crossing (kOrderMargin,
//      the margin the bins' depth culling uses, FrameBins.hpp).
// So a pixel centre whose edge functions clear their margins (the vertices' clip rounding, eta
// and Delta carried through each function) is inside or outside the triangle for its ray as for
// the exact line of sight. The bins (FrameBins) list for each tile every triangle a ray within
// kRayTolerancePx of its pixels can hit; Delta is held well below that.
//   4. The camera's user clip planes cut each ray (RobustRays' cutToClipPlanes): along it a plane's
//      value is s0 + s1 t, s0 = n . o + d and s1 = n . d each within gamma(3) of their terms'
//      sizes; the ray keeps t from -s0 / s1 on (s1 > 0) or up to it (s1 < 0), and a kept start
//      moves the origin there, o' = o + low d rounded. Let R bound |o| and |p| (inf-norm) for the
//      ray's origin o and any crossing p beyond o' (both lie within the near points' and the
//      scene's reach of the reference). A triangle whose three vertices' values all exceed
//      m = 2^-20 (|n|_1 R + |d|) is kept whole: the computed value at a crossing lies within
//      gamma(3) (|n|_1 3R + |d|) of the exact one, the cut point's within u |s0| of 0, so the
//      crossing lies on the kept side by far more than any rounding of the cut or of the
//      watertight t. One whose three values lie below -m is clipped whole. Any other may be cut at
//      some pixel and is never surely crossed (TriangleSetup::clipped).
//      The rounded origin translates the ray's line by e, |e| <= gamma(4) 2R per coordinate, which
//      at a crossing of clip w at least w_min moves its NDC by at most
//      (|m_x| + |m_w|) . |e| / (w_min - |m_w| . |e|) (rows' xyz, |x| <= 1): clipCutDeviation,
//      added to Delta. The watertight test then subtracts o', within max(nearExtent, the scene's
//      extent) of the reference: frameTerms widens nearExtent to that.

#include "clipray/compare/ScreenTriangleSetup.hpp"

#include <algorithm>
#include <cmath>

#include "clipray/intersect/FrameBins.hpp"

namespace clipray::screen {

namespace {

constexpr double kUnit = 0x1p-53;
constexpr double gamma(int n) {
  return n * kUnit / (1.0 - n * kUnit);
}
// Every bound below is doubled: the bounds' own arithmetic rounds (down by a few ulps at most),
// and the second-order terms of the perturbations are far below the first.
constexpr double kSlack = 2.0;

glm::dmat4 absolute(const glm::dmat4& m) {
  glm::dmat4 a;
  for (int c = 0; c < 4; ++c) a[c] = glm::abs(m[c]);
  return a;
}

glm::dvec3 row3(const glm::dmat4& m, int r) {
  return {m[0][r], m[1][r], m[2][r]};
}

// |a| x |b| as the cross product's error bound uses it: per component, the two products' sizes.
glm::dvec3 absCross(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 x = glm::abs(a), y = glm::abs(b);
  return {x.y * y.z + x.z * y.y, x.z * y.x + x.x * y.z, x.x * y.y + x.y * y.x};
}

// sum_k E_k(s) v_k / det for a vertex attribute v, as a plane over s, with its error bound.
struct InterpolatedPlane {
  double a = 0.0, b = 0.0, c = 0.0, error = kInf;
};

double maxAbs(const glm::dvec3& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

// The largest |o - reference| (inf-norm) of a ray's origin before the clip planes' cut, widened by
// 2^-20: on the near plane, at a corner of the frame's near face (the near points are affine in
// clip xy over it); under depth clamp the eye, or a parallel camera's near point moved
// parallelReach back along its unit direction.
double originExtentOf(const RobustRayGenerator& generator, const glm::dvec3& reference) {
  const DepthClampRays& clamp = generator.depthClamp();
  if (clamp.enabled && !generator.isParallel()) {
    return maxAbs(generator.eye() - reference) * (1.0 + 0x1p-20);
  }
  double extent = 0.0;
  for (const double x : {-1.0, 1.0}) {
    for (const double y : {-1.0, 1.0}) {
      const glm::dvec4 p =
          generator.worldFromClip() * glm::dvec4(x, y, generator.mode().nearNdcZ(), 1.0);
      extent = std::max(extent, maxAbs(glm::dvec3(p) / p.w - reference));
    }
  }
  if (clamp.enabled) extent += clamp.parallelReach;
  return extent * (1.0 + 0x1p-20);
}

// R of item 4 above: what bounds |o| and |p| of a ray's origin and crossings.
double clipReach(const RobustRayGenerator& generator, const glm::dvec3& reference,
                 double sceneExtent) {
  return (maxAbs(reference) + std::max(originExtentOf(generator, reference), sceneExtent)) *
         (1.0 + 0x1p-20);
}

// Whether the triangle of clip vertices h_k (each within error_k of its exact x, y and w) may meet
// the eye box of depth clamp (FrameTerms::eyeBoxW): not when the box's axes separate them (all
// three beyond one of its faces), nor when the triangle's plane in clip (x, y, w) misses it. That
// plane is n . q = det[h0, h1, h2] with n = (h1 - h0) x (h2 - h0), so its value at the box's
// centre (0, 0, c) is n_w c - det (det within detError); the box reaches |n_x| b + |n_y| b +
// |n_w| h of it (half sizes b, b, h), and n's rounding and the vertices' moves add at most
// gamma(4) |n terms| + 4 max error_k (|h1 - h0|_1 + |h2 - h0|_1) per component.
bool mayMeetEyeBox(const FrameTerms& frame, const glm::dvec4 (&clip)[3], const double (&error)[3],
                   double det, double detError) {
  const double b = frame.eyeBoxXY, wHigh = frame.eyeBoxW, wLow = -frame.eyeBoxBelowW;
  const auto allThree = [](auto beyondFace) {
    return beyondFace(0) && beyondFace(1) && beyondFace(2);
  };
  if (allThree([&](int j) { return clip[j].w - error[j] >= wHigh; }) ||
      allThree([&](int j) { return clip[j].w + error[j] < wLow; }) ||
      allThree([&](int j) { return clip[j].x - error[j] > b; }) ||
      allThree([&](int j) { return clip[j].x + error[j] < -b; }) ||
      allThree([&](int j) { return clip[j].y - error[j] > b; }) ||
      allThree([&](int j) { return clip[j].y + error[j] < -b; })) {
    return false;
  }
  const glm::dvec3 p(clip[1].x - clip[0].x, clip[1].y - clip[0].y, clip[1].w - clip[0].w);
  const glm::dvec3 q(clip[2].x - clip[0].x, clip[2].y - clip[0].y, clip[2].w - clip[0].w);
  const glm::dvec3 n = glm::cross(p, q);
  const double moves = 4.0 * std::max({error[0], error[1], error[2]}) *
                       (std::abs(p.x) + std::abs(p.y) + std::abs(p.z) + std::abs(q.x) +
                        std::abs(q.y) + std::abs(q.z));
  const glm::dvec3 nError = gamma(4) * absCross(p, q) + moves;
  const double centre = 0.5 * (wHigh + wLow), half = 0.5 * (wHigh - wLow);
  const double value = n.z * centre - det;
  const double reach = (std::abs(n.x) + nError.x + std::abs(n.y) + nError.y) * b +
                       (std::abs(n.z) + nError.z) * (half + std::abs(centre)) + detError;
  return !(std::abs(value) > kSlack * reach);
}

}  // namespace

// Delta: how far, in NDC, any point of a pixel's robust ray may project from the pixel centre
// s = (x, y) (|x|, |y| < 1); nullopt where the camera's rays have no such bound here.
//  - The near point o = worldFromClip (x, y, z_n, 1), divided by its w. With P = worldFromClip as
//    computed and R = M P - I (|R| <= |fl(M P) - I| + gamma(5) |M| |P|), M (o, 1) is proportional
//    to (I + R) s~ + M e with |e| <= gamma(5) |P| |s~| (the product and the division), s~ =
//    (x, y, z_n, 1): clip error q = |R| |s~| + gamma(6) |M| |P| |s~| against a w of 1, and an NDC
//    error (q_xy + q_w) / (1 - q_w).
//  - The direction d = x (m_y x m_w) + y (m_w x m_x) + m_x x m_y (rows' xyz, each cross product
//    within gamma(2) |a| x |b|, two fused multiply-adds within gamma(2) of the sum of the terms'
//    sizes, then normalized within gamma(5) of each component): |delta d| <= e_D + gamma(8) S_D.
//    Along o + t d, clip x - x w grows by (m_x - x m_w) . delta d per unit t while w grows by
//    m_w . d = det(m_x, m_y, m_w) (the same for every pixel): the NDC error stays below
//    (|m_x| + |m_w|) . |delta d| / (|det| - its error). A parallel camera's w is constant: the
//    error grows with t up to tMax (the same for every pixel: the near and far planes are
//    parallel), |m_x| . |delta d| tMax / (|d| w).
namespace {

// |fl(M P) - I| + gamma(5) |M| |P|: what bounds M P - I for the matrices as computed.
glm::dmat4 inverseResidual(const glm::dmat4& m, const glm::dmat4& p) {
  glm::dmat4 residual = absolute(m * p - glm::dmat4(1.0));
  const glm::dmat4 sizes = absolute(m) * absolute(p);
  for (int c = 0; c < 4; ++c) residual[c] += gamma(5) * sizes[c];
  return residual;
}

// The direction's error bound |delta d| and what the perspective stray reads (rayDeviation's
// comment): d3 = m_x x m_y and the cross products' error.
struct DirectionTerms {
  glm::dvec3 d3, crossError, deltaD;
};

DirectionTerms directionTerms(const glm::dmat4& m) {
  const glm::dvec3 mx = row3(m, 0), my = row3(m, 1), mw = row3(m, 3);
  const glm::dvec3 d1 = glm::cross(my, mw), d2 = glm::cross(mw, mx), d3 = glm::cross(mx, my);
  const glm::dvec3 crossError = gamma(2) * (absCross(my, mw) + absCross(mw, mx) + absCross(mx, my));
  const glm::dvec3 sizeD = glm::abs(d1) + glm::abs(d2) + glm::abs(d3);
  return {d3, crossError, crossError + gamma(8) * sizeD};
}

// A perspective camera's rays: the NDC stray their direction adds (over the whole ray), from the
// rate of clip w along the unnormalized direction, |det| less its error; nullopt with the reason.
std::optional<double> perspectiveStray(const RobustRayGenerator& generator,
                                       const DirectionTerms& terms, std::string& reason) {
  // The bound needs w to grow along the ray (the robust direction's sign: away from the eye).
  if (!(generator.facingSign() > 0.0)) {
    reason = "rays along which clip w falls (a near plane on the eye's visible side)";
    return std::nullopt;
  }
  const glm::dmat4& m = generator.clipFromWorld();
  const glm::dvec3 mx = row3(m, 0), my = row3(m, 1), mw = row3(m, 3);
  const double det = glm::dot(mw, terms.d3);
  const double detError = gamma(3) * glm::dot(glm::abs(mw), glm::abs(terms.d3)) +
                          glm::dot(glm::abs(mw), terms.crossError + terms.deltaD);
  const double rate = std::abs(det) - detError;
  if (!(rate > 0.0)) {
    reason = "the rays' rate of clip w has no bound";
    return std::nullopt;
  }
  return std::max(glm::dot(glm::abs(mx) + glm::abs(mw), terms.deltaD),
                  glm::dot(glm::abs(my) + glm::abs(mw), terms.deltaD)) /
         rate;
}

}  // namespace

std::optional<double> rayDeviation(const RobustRayGenerator& generator, std::string& reason) {
  const glm::dmat4& m = generator.clipFromWorld();
  const glm::dmat4& p = generator.worldFromClip();
  const glm::dmat4 absM = absolute(m), absP = absolute(p);
  const glm::dmat4 residual = inverseResidual(m, p);
  const glm::dvec4 s(1.0, 1.0, std::abs(generator.mode().nearNdcZ()), 1.0);
  const glm::dvec4 q = residual * s + gamma(6) * (absM * (absP * s));
  if (!(q.w < 0.25)) {
    reason = "the near points' rounding has no bound (matrix times its inverse is far from I)";
    return std::nullopt;
  }
  const double nearPoint = (std::max(q.x, q.y) + q.w) / (1.0 - q.w);

  const DirectionTerms terms = directionTerms(m);
  double direction = 0.0;
  if (generator.isParallel()) {
    const double w = std::abs(m[3][3]);
    const double tMax = generator.generate({0.0, 0.0}).tMax;
    const double length = glm::length(terms.d3) - glm::length(terms.deltaD);
    if (!std::isfinite(tMax) || !(w > 0.0) || !(length > 0.0)) {
      reason = "a parallel camera without a finite far plane";
      return std::nullopt;
    }
    const glm::dvec3 mx = row3(m, 0), my = row3(m, 1);
    const double stray =
        std::max(glm::dot(glm::abs(mx), terms.deltaD), glm::dot(glm::abs(my), terms.deltaD));
    direction = stray * tMax * (1.0 + 0x1p-20) / (length * w);
  } else {
    const std::optional<double> stray = perspectiveStray(generator, terms, reason);
    if (!stray) return std::nullopt;
    direction = *stray;
  }
  return kSlack * (nearPoint + direction);
}

// Under depth clamp the rays' origins move (RobustRays' reachForDepthClamp):
//  - A parallel camera's near point o moves back to o - r d (r = parallelReach, |d| = 1 within
//    gamma(5)), rounded: the line moves by at most gamma(2) (|o| + r |d|) per coordinate, which
//    shifts its NDC by (|m_x| . e) / w at the constant w; the direction's stray grows with t up
//    to the longer tMax, which rayDeviation reads from the generator.
//  - A perspective camera's origin is the eye as computed, E' = fl(c / c_w) with c = P column 2:
//    M (c / c_w, 1) = (M c) / c_w exactly (its w part is c_w / c_w), and M c is column 2 of M P,
//    within the residual of e_2, so E''s clip x, y and w are within e_r = R[2][r] / |c_w| +
//    gamma(2) |m_r| . |E'| of 0. Along E' + t d, x - s w = (x_E - s w_E) + t (m_x - s m_w) .
//    delta d and w = w_E + t (m_w . d) with m_w . d >= rate: the NDC stray at clip w is at most
//    direction + (e_x + e_w + direction e_w) / w (direction: the stray rayDeviation bounds per
//    unit of w, |s| <= 1), so at every crossing of w >= wLeast its value there. The points of a
//    ray below wLeast have |x|, |y| <= wLeast + e_x + e_w + direction (wLeast + e_w), w >= -e_w:
//    the eye box, which no triangle may meet (setupTriangle's nearEye). wLeast = 2^-16 times the
//    near plane's least w: far enough from the eye that the bins' cut there rounds little, near
//    enough that a triangle meets the box only when it passes that close to the eye.
std::optional<DepthClampReach> depthClampDeviation(const RobustRayGenerator& generator,
                                                   std::string& reason) {
  const glm::dmat4& m = generator.clipFromWorld();
  const glm::dmat4& p = generator.worldFromClip();
  const std::optional<double> wNear = FrameBins::nearPlaneW(m, generator.mode());
  if (!wNear) {
    reason = "depth clamp where the near plane is not in front of the camera";
    return std::nullopt;
  }
  DepthClampReach reach;
  if (generator.isParallel()) {
    const std::optional<double> delta = rayDeviation(generator, reason);
    if (!delta) return std::nullopt;
    // |o| + r, o a near point (originExtentOf about the world origin).
    const double e = gamma(2) * originExtentOf(generator, glm::dvec3(0.0)) + kUnit;
    const glm::dvec3 mx = glm::abs(row3(m, 0)), my = glm::abs(row3(m, 1));
    const double shift = std::max(mx.x + mx.y + mx.z, my.x + my.y + my.z) * e / std::abs(m[3][3]);
    reach.delta = *delta + kSlack * shift;
    reach.wLeast = 0.5 * *wNear;  // the bins' default: every point of the frame has w = m[3][3]
    if (!std::isfinite(reach.delta)) {
      reason = "the depth-clamped rays' stray has no bound";
      return std::nullopt;
    }
    return reach;
  }
  const DirectionTerms terms = directionTerms(m);
  const std::optional<double> stray = perspectiveStray(generator, terms, reason);
  if (!stray) return std::nullopt;
  const glm::dmat4 residual = inverseResidual(m, p);
  const double cw = std::abs(p[2][3]);
  const glm::dvec3 eye = glm::abs(generator.eye());
  const auto eyeClip = [&](int r) {
    return residual[2][r] / cw + gamma(2) * glm::dot(glm::abs(row3(m, r)), eye);
  };
  const double ex = std::max(eyeClip(0), eyeClip(1)), ew = eyeClip(3);
  reach.wLeast = 0x1p-16 * *wNear;
  const double direction = *stray;
  if (!(cw > 0.0) || !(4.0 * ew < reach.wLeast) || !std::isfinite(ex)) {
    reason = "the depth-clamped rays' eye has no bound";
    return std::nullopt;
  }
  reach.delta = kSlack * (direction + (ex + ew + direction * ew) / reach.wLeast);
  reach.eyeBoxW = reach.wLeast;
  reach.eyeBoxBelowW = kSlack * ew;
  reach.eyeBoxXY = kSlack * (reach.wLeast + ex + ew + direction * (reach.wLeast + ew));
  return reach;
}

std::optional<double> clipCutDeviation(const RobustRayGenerator& generator,
                                       const glm::dvec3& reference, double sceneExtent,
                                       std::string& reason, const DepthClampReach* clamp) {
  if (generator.clipPlanes().empty()) return 0.0;
  const glm::dmat4& m = generator.clipFromWorld();
  // The least clip w of a crossing: a parallel camera's is constant; a perspective camera's grows
  // along each line of sight from the eye, so it is least at the near point, whose clip w is
  // 1 / w_near with w_near = worldFromClip row 3 . (x, y, z_n, 1), affine in (x, y): its largest
  // value over the frame lies at a corner. Under depth clamp the crossings lie beyond wLeast
  // (depthClampDeviation).
  double wMin = 0.0;
  if (generator.isParallel()) {
    wMin = std::abs(m[3][3]);
  } else if (clamp) {
    wMin = clamp->wLeast;
  } else {
    const glm::dmat4& p = generator.worldFromClip();
    double wNear = -kInf;
    for (const double x : {-1.0, 1.0}) {
      for (const double y : {-1.0, 1.0}) {
        wNear = std::max(
            wNear, p[0][3] * x + p[1][3] * y + p[2][3] * generator.mode().nearNdcZ() + p[3][3]);
      }
    }
    wMin = (1.0 - 0x1p-20) / wNear;
  }
  const double e = gamma(4) * 2.0 * clipReach(generator, reference, sceneExtent);
  const glm::dvec3 mx = glm::abs(row3(m, 0)), my = glm::abs(row3(m, 1)), mw = glm::abs(row3(m, 3));
  const double wMove = (mw.x + mw.y + mw.z) * e;
  const double deviation =
      (std::max(mx.x + mx.y + mx.z, my.x + my.y + my.z) * e + wMove) / (wMin - wMove);
  if (!(wMin > 0.0) || !std::isfinite(wMin) || !(wMin - wMove > 0.0) || !std::isfinite(deviation)) {
    reason = "the clip planes' cut of the rays has no bound (the near points' clip w has none)";
    return std::nullopt;
  }
  return kSlack * deviation;
}

FrameTerms frameTerms(const PickingCamera& camera, const RobustRayGenerator& generator,
                      const glm::dmat4& clipFromRelative, const glm::dvec3& reference, double delta,
                      double sceneExtent, const DepthClampReach* clamp) {
  FrameTerms terms;
  terms.viewport = camera.viewport;
  terms.delta = delta;
  terms.clipFromRelative = clipFromRelative;
  terms.absClipFromRelative = absolute(clipFromRelative);
  terms.translationError =
      gamma(5) * (absolute(camera.clipFromWorld) * glm::dvec4(glm::abs(reference), 1.0));
  for (int r = 0; r < 4; ++r) {
    terms.rowSize[r] = std::abs(camera.clipFromWorld[0][r]) + std::abs(camera.clipFromWorld[1][r]) +
                       std::abs(camera.clipFromWorld[2][r]);
  }
  const DepthMode mode = camera.mode;
  terms.nearExtent = originExtentOf(generator, reference);
  if (!generator.clipPlanes().empty()) {
    // A cut ray's origin lies anywhere up to its crossing (item 4 above).
    terms.nearExtent = std::max(terms.nearExtent, sceneExtent * (1.0 + 0x1p-20));
    const double reach = clipReach(generator, reference, sceneExtent);
    for (const glm::dvec4& plane : generator.clipPlanes()) {
      const glm::dvec3 n(plane);
      // Folded to the reference: n . (p_relative + reference) + d, within gamma(3) of its terms.
      terms.clipPlanes.emplace_back(n, glm::dot(n, reference) + plane.w);
      terms.clipMargins.push_back(
          0x1p-20 * ((std::abs(n.x) + std::abs(n.y) + std::abs(n.z)) * reach + std::abs(plane.w)));
    }
  }
  terms.zNear = mode.nearNdcZ();
  terms.sigma = mode.farNdcZ() > mode.nearNdcZ() ? 1.0 : -1.0;
  // An infinite far plane: row 2 - z_far row 3 has no xyz part (RobustRays' far plane).
  const glm::dvec3 farXyz =
      row3(camera.clipFromWorld, 2) - mode.farNdcZ() * row3(camera.clipFromWorld, 3);
  terms.keyFar = farXyz == glm::dvec3(0.0) ? kInf : std::abs(mode.farNdcZ() - mode.nearNdcZ());
  if (clamp) {
    // The rays start at the eye (a parallel camera's parallelReach behind the near points) and
    // reach beyond the far plane where beyondFar says so (RobustRays' DepthClampRays).
    terms.keyNearIn = terms.keyNearOut = -kInf;
    if (generator.depthClamp().beyondFar) terms.keyFar = kInf;
    terms.eyeBoxW = clamp->eyeBoxW;
    terms.eyeBoxXY = clamp->eyeBoxXY;
    terms.eyeBoxBelowW = clamp->eyeBoxBelowW;
  }
  return terms;
}

TriangleSetup setupTriangle(const FrameTerms& frame, const detail::BvhTriangle& tri,
                            TrianglePlanes* planes, ClipEdge* clipEdges) {
  TriangleSetup setup;
  setup.primitiveId = tri.primitiveId;
  if (clipEdges) std::fill_n(clipEdges, kMaxClipCuts, ClipEdge{});
  const glm::dvec3 vertex[3] = {tri.a, tri.b, tri.c};
  glm::dvec4 clip[3];
  double error[3], zError[3], size[3];
  for (int j = 0; j < 3; ++j) {
    clip[j] = frame.clipFromRelative * glm::dvec4(vertex[j], 1.0);
    // The watertight test's vertex moves (eta, item 2 above): the origin's subtraction, the shear
    // and the edge function's product round once each per coordinate, on coordinates no larger
    // than |vertex| + |origin| (the shear factors are at most 1).
    const double eta = gamma(8) * (maxAbs(vertex[j]) + frame.nearExtent);
    const glm::dvec4 e =
        gamma(6) * (frame.absClipFromRelative * glm::dvec4(glm::abs(vertex[j]), 1.0)) +
        frame.translationError + eta * frame.rowSize;
    error[j] = std::max({e.x, e.y, e.w});
    zError[j] = e.z;
    size[j] = std::abs(clip[j].x) + std::abs(clip[j].y) + std::abs(clip[j].w);
  }
  double magnitude[3], evaluation[3];
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3, l = (k + 2) % 3;
    const glm::dvec4 &p = clip[j], &r = clip[l];
    setup.a[k] = p.y * r.w - p.w * r.y;
    setup.b[k] = p.w * r.x - p.x * r.w;
    setup.c[k] = p.x * r.y - p.y * r.x;
    magnitude[k] = std::abs(p.y * r.w) + std::abs(p.w * r.y) + std::abs(p.w * r.x) +
                   std::abs(p.x * r.w) + std::abs(p.x * r.y) + std::abs(p.y * r.x);
    // det[p, r, s] with |s| <= (1, 1, 1): the coefficients' and the evaluation's roundings
    // (gamma(4) of the terms' sizes), and each vertex's move times the size of the other's cross
    // product with s (at most 2 |other|_1).
    evaluation[k] = gamma(4) * magnitude[k] + 2.0 * (error[j] * size[l] + error[l] * size[j]);
    setup.margin[k] =
        kSlack * (evaluation[k] + frame.delta * (std::abs(setup.a[k]) + std::abs(setup.b[k])));
  }
  // det[h0, h1, h2] = E_0 at h0; a vertex's move changes it by at most its size times the
  // cofactor's, which is that vertex's edge function's coefficients.
  const double det = setup.a[0] * clip[0].x + setup.b[0] * clip[0].y + setup.c[0] * clip[0].w;
  const double hSize = std::max({std::abs(clip[0].x), std::abs(clip[0].y), std::abs(clip[0].w)});
  const double detError = kSlack * (gamma(5) * magnitude[0] * hSize + error[0] * magnitude[0] +
                                    error[1] * magnitude[1] + error[2] * magnitude[2]);
  if (std::abs(det) > detError) setup.sign = det > 0.0 ? 1.0 : -1.0;
  if (frame.eyeBoxW > 0.0) setup.nearEye = mayMeetEyeBox(frame, clip, error, det, detError);

  // The depth plane: z(s) = sum_k E_k(s) z_k / det (barycentrics E_k / sum E, clip w det / sum E).
  // Its error: each E_k's (as above) times |z_k|, each z_k's times |E_k| <= magnitude_k, the
  // sums' and products' roundings (gamma(4)), det's error times |z|, and the ray's reach Delta
  // times the plane's slopes.
  // A vertex attribute's value over w at the line of sight's crossing, sum_k E_k(s) v_k / det, as
  // a plane over s, with its error: each E_k's (as above) times |v_k|, each v_k's error times |E_k|
  // <= magnitude_k, the sums' and products' roundings (gamma(4)), det's error times the plane's
  // size, and the ray's reach Delta times its slopes.
  const auto interpolated = [&](const double(&value)[3], const double(&valueError)[3]) {
    InterpolatedPlane plane;
    double sa = 0.0, sb = 0.0, sc = 0.0, spread = 0.0;
    for (int k = 0; k < 3; ++k) {
      sa += setup.a[k] * value[k];
      sb += setup.b[k] * value[k];
      sc += setup.c[k] * value[k];
      spread += (evaluation[k] + gamma(4) * magnitude[k]) * std::abs(value[k]) +
                magnitude[k] * valueError[k];
    }
    plane.a = sa / det;
    plane.b = sb / det;
    plane.c = sc / det;
    const double planeSize = std::abs(plane.a) + std::abs(plane.b) + std::abs(plane.c);
    plane.error = kSlack * (spread / std::abs(det) + gamma(4) * planeSize +
                            planeSize * detError / std::abs(det) +
                            frame.delta * (std::abs(plane.a) + std::abs(plane.b)));
    if (!std::isfinite(plane.error)) plane.error = kInf;
    return plane;
  };
  if (setup.sign != 0.0) {
    const double z[3] = {clip[0].z, clip[1].z, clip[2].z};
    const InterpolatedPlane depth = interpolated(z, zError);
    setup.za = depth.a;
    setup.zb = depth.b;
    setup.zc = depth.c;
    setup.depthError = depth.error;
    if (planes) {
      // 1 / w(s) = sum_k E_k(s) / det: the depth plane's sum with every z_k = 1 (exact), so its
      // error has the same terms with |z_k| = 1 and no z_k error.
      double spreadW = 0.0;
      for (int k = 0; k < 3; ++k) spreadW += evaluation[k] + gamma(4) * magnitude[k];
      TrianglePlanes& p = *planes;
      p.za = setup.za, p.zb = setup.zb, p.zc = setup.zc, p.depthError = setup.depthError;
      p.ra = (setup.a[0] + setup.a[1] + setup.a[2]) / det;
      p.rb = (setup.b[0] + setup.b[1] + setup.b[2]) / det;
      p.rc = (setup.c[0] + setup.c[1] + setup.c[2]) / det;
      const double rSize = std::abs(p.ra) + std::abs(p.rb) + std::abs(p.rc);
      p.reciprocalWError =
          kSlack * (spreadW / std::abs(det) + gamma(4) * rSize + rSize * detError / std::abs(det) +
                    frame.delta * (std::abs(p.ra) + std::abs(p.rb)));
      if (!std::isfinite(p.reciprocalWError)) p.reciprocalWError = kInf;
    }
  } else if (planes) {
    *planes = {0.0, 0.0, 0.0, kInf, 0.0, 0.0, 0.0, kInf};  // never decided: no certain orientation
  }

  // The pixels it may matter to: its vertices' projections, when all lie in front of the eye,
  // padded by half a pixel, where each edge's margin reaches less than a quarter pixel from the
  // edge (|E| <= margin lies within sqrt(2) margin / (|2 a / width| + |2 b / height|) pixels of
  // it); else every pixel.
  const Viewport viewport = frame.viewport;
  setup.x0 = 0;
  setup.x1 = viewport.width - 1;
  setup.y0 = 0;
  setup.y1 = viewport.height - 1;
  bool narrowMargins = true;
  for (int k = 0; k < 3; ++k) {
    const double slope =
        std::abs(2.0 * setup.a[k] / viewport.width) + std::abs(2.0 * setup.b[k] / viewport.height);
    narrowMargins = narrowMargins && 1.5 * setup.margin[k] < 0.25 * slope;
  }
  if (narrowMargins && clip[0].w > 0.0 && clip[1].w > 0.0 && clip[2].w > 0.0) {
    double xMin = kInf, xMax = -kInf, yMin = kInf, yMax = -kInf;
    for (const glm::dvec4& c : clip) {
      xMin = std::min(xMin, c.x / c.w);
      xMax = std::max(xMax, c.x / c.w);
      yMin = std::min(yMin, c.y / c.w);
      yMax = std::max(yMax, c.y / c.w);
    }
    // Pixel i's centre is at NDC (2 i + 1) / width - 1.
    const auto toPixel = [](double ndc, int extent) { return ((ndc + 1.0) * extent - 1.0) * 0.5; };
    const double pad = 0.5;
    const double px0 = toPixel(xMin, viewport.width) - pad,
                 px1 = toPixel(xMax, viewport.width) + pad;
    const double py0 = toPixel(yMin, viewport.height) - pad,
                 py1 = toPixel(yMax, viewport.height) + pad;
    if (std::isfinite(px0 + px1 + py0 + py1)) {
      setup.x0 = static_cast<int>(std::clamp(std::ceil(px0), -1.0, double(viewport.width)));
      setup.x1 = static_cast<int>(std::clamp(std::floor(px1), -1.0, double(viewport.width)));
      setup.y0 = static_cast<int>(std::clamp(std::ceil(py0), -1.0, double(viewport.height)));
      setup.y1 = static_cast<int>(std::clamp(std::floor(py1), -1.0, double(viewport.height)));
    }
  }
  // The user clip planes (item 4 above): kept whole by all, clipped whole by one, or cut. A plane's
  // value over w at the crossing is sum_k E_k(s) v_k / det, so v > m at the crossing where the
  // plane of the values v_k - m is positive (w > 0 in the view volume) and v < -m where that of
  // v_k + m is negative, each beyond its error (v_k's within gamma(5) of its terms, folding the
  // reference included): what clipEdges keep for each plane that cuts the triangle.
  int cuts = 0;
  for (std::size_t k = 0; k < frame.clipPlanes.size(); ++k) {
    const glm::dvec4& plane = frame.clipPlanes[k];
    const double margin = frame.clipMargins[k];
    bool kept = true, dropped = true;
    double keptValue[3], droppedValue[3], valueError[3];
    for (int j = 0; j < 3; ++j) {
      const double value = glm::dot(glm::dvec3(plane), vertex[j]) + plane.w;
      kept = kept && value > margin;
      dropped = dropped && value < -margin;
      keptValue[j] = value - margin;
      droppedValue[j] = value + margin;
      valueError[j] = gamma(5) * (glm::dot(glm::abs(glm::dvec3(plane)), glm::abs(vertex[j])) +
                                  std::abs(plane.w)) +
                      gamma(1) * margin;
    }
    if (dropped) {
      setup.x0 = setup.y0 = 0;
      setup.x1 = setup.y1 = -1;
      setup.clipped = false;
      break;
    }
    if (kept) continue;
    setup.clipped = true;
    if (cuts < kMaxClipCuts && clipEdges && setup.sign != 0.0) {
      const InterpolatedPlane keep = interpolated(keptValue, valueError);
      const InterpolatedPlane clipAway = interpolated(droppedValue, valueError);
      clipEdges[cuts] = {keep.a,     keep.b,     keep.c,         keep.error, clipAway.a,
                         clipAway.b, clipAway.c, clipAway.error, true};
    }
    ++cuts;
  }
  // Cut by more planes than it has edges for: never sure anywhere.
  if (clipEdges && cuts > kMaxClipCuts) std::fill_n(clipEdges, kMaxClipCuts, ClipEdge{});
  // A certain orientation turns the edge functions inside out where det < 0 (a product by -1 is
  // exact): the inside is then where every E_k exceeds its margin, for either winding.
  if (setup.sign < 0.0) {
    for (int k = 0; k < 3; ++k) {
      setup.a[k] = -setup.a[k];
      setup.b[k] = -setup.b[k];
      setup.c[k] = -setup.c[k];
    }
  }
  return setup;
}

}  // namespace clipray::screen

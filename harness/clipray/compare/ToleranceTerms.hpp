#pragma once
// Internal to compare/: the arithmetic the tolerance model and the per-pixel classification share
// (float rounding bounds, the depth quantum, the tolerance of a triangle hit from its polygon's
// terms), inline so that both compute it with the same operations and get the same bits.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"

namespace clipray::detail {

inline constexpr double kFloatUnitRoundoff = 0x1p-24;   // u for IEEE single precision
inline constexpr double kDoubleUnitRoundoff = 0x1p-53;  // u_d for IEEE double precision
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// a / b and c / d. With SSE2 as one two-lane division (the divider's throughput bounds the
// per-pixel loops): each lane is the correctly rounded IEEE quotient, the scalar division's.
inline std::pair<double, double> divideTwo(double a, double b, double c, double d) {
#if defined(__SSE2__)
  const __m128d quotients = _mm_div_pd(_mm_set_pd(c, a), _mm_set_pd(d, b));
  return {_mm_cvtsd_f64(quotients), _mm_cvtsd_f64(_mm_unpackhi_pd(quotients, quotients))};
#else
  return {a / b, c / d};
#endif
}

// depthQuantum (Conventions.cpp), exactly, without a library call per pixel for Float32:
// nextafter(d, +inf) of a finite non-negative float d is the float whose bit pattern is one more
// (across binades too, at 0 the smallest subnormal, at FLT_MAX +inf as nextafter gives). Infinite
// and NaN depths, and the unorm formats (one quantum at every depth), take depthQuantum itself.
inline double quantumAt(DepthFormat format, double windowDepth) {
  const float d = static_cast<float>(std::fabs(windowDepth));
  const auto bits = std::bit_cast<std::uint32_t>(d);
  if (format != DepthFormat::Float32 || bits >= 0x7f800000u) {
    return depthQuantum(format, windowDepth);
  }
  const float next = std::bit_cast<float>(bits + 1u);
  return std::max(static_cast<double>(next - d),
                  static_cast<double>(std::numeric_limits<float>::min()));
}

// The tolerance model of a triangle hit (see depthToleranceAtClip) from its screen polygon's
// PixelTerms and the hit's clip coordinates c, with z_ndc = c.z / c.w, its window depth and the
// depth quantum there given (the per-pixel classification has them already). Terms is
// ToleranceModel::PixelTerms.
template <class Terms>
inline double triangleDepthTolerance(const Terms& terms, const glm::dvec4& c, double zNdc,
                                     double depth, double storage, double toWindow,
                                     double subpixelStep, Viewport viewport) {
  const double u = kFloatUnitRoundoff;
  const glm::dvec4& bound = terms.clipErrorBound;
  // 1. Storage: one quantum of the depth format at this depth (given).
  // 2. Vertex transform in float, interpolated: dz_ndc = (dz + |z_ndc| dw) / w, plus the GPU's
  //    divide and depth-range mapping (2u relative).
  // 3. Vertex positions snapped to the subpixel grid and moved by the float xy error
  //    ((dx + |x_ndc| dw) / w in pixels, likewise y): the depth plane shifts by |gradient| times
  //    that displacement.
  // The quotients of 2 and 3 are taken in pairs (see divideTwo).
  const auto [xNdc, yNdc] = divideTwo(c.x, c.w, c.y, c.w);
  const double xyError = std::max((bound.x + std::abs(xNdc) * bound.w) * 0.5 * viewport.width,
                                  (bound.y + std::abs(yNdc) * bound.w) * 0.5 * viewport.height);
  const auto [vertexNdc, xyErrorPixels] =
      divideTwo(bound.z + std::abs(zNdc) * bound.w, std::abs(c.w), xyError, std::abs(c.w));
  const double vertex = vertexNdc * toWindow + 2.0 * u * std::abs(depth);
  const double xyShift = subpixelStep + xyErrorPixels;
  const double snap = terms.gradient * xyShift;
  // 4. Plane evaluation in float: terms.interpolation (see pixelTermsOf).
  return storage + vertex + snap + terms.interpolation;
}

// The same tolerance where the hit is known by its NDC (x, y, z) and its reciprocal clip w
// instead of its clip coordinates (the screen path's planes, TrianglePlanes in Frames.hpp): the
// terms above with the quotients by |w| taken as products by 1 / w. Not the same bits as
// triangleDepthTolerance: the inputs differ from a ray's hit within their planes' bounds.
template <class Terms>
inline double triangleDepthToleranceAtNdc(const Terms& terms, double xNdc, double yNdc, double zNdc,
                                          double reciprocalW, double depth, double storage,
                                          double toWindow, double subpixelStep, Viewport viewport) {
  const double u = kFloatUnitRoundoff;
  const glm::dvec4& bound = terms.clipErrorBound;
  const double xyError = std::max((bound.x + std::abs(xNdc) * bound.w) * 0.5 * viewport.width,
                                  (bound.y + std::abs(yNdc) * bound.w) * 0.5 * viewport.height);
  const double vertex =
      (bound.z + std::abs(zNdc) * bound.w) * reciprocalW * toWindow + 2.0 * u * std::abs(depth);
  const double snap = terms.gradient * (subpixelStep + xyError * reciprocalW);
  return storage + vertex + snap + terms.interpolation;
}

}  // namespace clipray::detail

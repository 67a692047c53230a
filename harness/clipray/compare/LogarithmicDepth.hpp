#pragma once
// A depth written by the mesh fragment shader (Camera::logarithmicDepth, Scene.hpp): three.js's
// logarithmicDepthBuffer and Outerra's log depth store L(w) = log2(1 + C w) / log2(1 + C far) of
// the fragment's clip w, not the projective depth of its NDC z (1 - L under reversed-Z, so that
// GL_GREATER still keeps the nearest). The convention's NDC z only decides what the near and far
// planes clip; what is stored is a function of w alone, the same under NO and ZO.
//
// Tolerance of the stored depth (derivation: docs/reconcile.md, "Logarithmic depth"), u = 2^-24,
// s = 1 / log2(1 + C far) the scale, A = 1 + C w the log's argument:
//   1. The fragment's A: 1 + C gl_Position.w in float at each vertex (2u relative), interpolated
//      perspective-correctly in float: A / w and 1 / w evaluated as planes from vertex values
//      that may be w / w_min larger than at the fragment (w_min: the clipped polygon's smallest
//      w), 8u of the largest each, then divided: (16 w / w_min + 3) u relative in all. The
//      vertices' own w error (the float transform, ToleranceModel's clipErrorBound.w) and the
//      subpixel snap moving the triangle under the pixel centre (|grad w| times the shift in
//      pixels) add C dw / A. d L / d A = s / (A ln 2): relative error e of A is s e / ln 2 of L.
//   2. log2 in float (GLSL 4.50 8.3's precision table): absolute 2^-21 for A in [0.5, 2], 3 ulp
//      outside: at most s 2^-21 + 3 * 2^-23 L.
//   3. The scale rounded to a float uniform and the product rounded: 2u L.
//   4. 1 - L under reversed-Z: u (half an ulp below 1 is 2^-25; one ulp for margin).
//   5. Storage: one quantum of the depth format at the stored depth.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "clipray/Conventions.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {

// The mapping of one camera under one convention. Its scale is fixed at construction: the
// compare evaluates the mapping at every pixel, and the scale's log2 would otherwise cost one per
// call (the same bits: it is the same expression).
class LogDepthMapping {
 public:
  LogDepthMapping(double constant, double far, bool reversed)
      : constant_(constant),
        far_(far),
        reversed_(reversed),
        scale_(1.0 / std::log2(1.0 + constant * far)) {}
  bool operator==(const LogDepthMapping&) const = default;

  double constant() const { return constant_; }  // C (three.js: 1)
  double far() const { return far_; }            // L(far) = 1
  // The shader writes 1 - L (reversed-Z: near is the greater depth).
  bool reversed() const { return reversed_; }
  // s = 1 / log2(1 + C far): three.js's logDepthBufFC * 0.5.
  double scale() const { return scale_; }
  // L(w), or 1 - L(w) reversed: the depth the shader writes for clip w.
  double windowDepth(double clipW) const {
    const double l = std::log2(1.0 + constant_ * clipW) * scale_;
    return reversed_ ? 1.0 - l : l;
  }
  // Its inverse: the clip w whose fragment stores `depth`.
  double clipWOfWindowDepth(double depth) const {
    const double l = reversed_ ? 1.0 - depth : depth;
    return (std::exp2(l / scale_) - 1.0) / constant_;
  }
  // d(window depth) / d(clip w): s C / ((1 + C w) ln 2), negative reversed.
  double slope(double clipW) const {
    const double s = scale_ * constant_ / ((1.0 + constant_ * clipW) * std::numbers::ln2);
    return reversed_ ? -s : s;
  }
  // Where 1 / w lies within reciprocalWError of reciprocalW (> 0): w's range, and how far L (or
  // 1 - L) over it may lie from `depth`, windowDepth(1 / reciprocalW) as computed, both
  // evaluations' rounding of log2 and of 1 + C w included (a few ulp of L and of the scale). L
  // rises ever more slowly with w, so its slope at the range's low end bounds it. nullopt where
  // the range reaches w <= 0.
  struct Reach {
    double wLow, wHigh, depth;
  };
  std::optional<Reach> reachOver(double reciprocalW, double reciprocalWError, double depth) const {
    if (!(reciprocalW - reciprocalWError > 0.0)) return std::nullopt;
    const double wLow = 1.0 / (reciprocalW + reciprocalWError);
    const double wHigh = 1.0 / (reciprocalW - reciprocalWError);
    return Reach{wLow, wHigh,
                 std::abs(slope(wLow)) * (wHigh - wLow) + 0x1p-48 * (std::abs(depth) + scale_)};
  }
  // The tolerance above for a fragment at clip w whose w may be off by wError (vertex rounding
  // and snap, world units of w), w_min the smallest w of its clipped polygon, stored with
  // quantum `storage`.
  double tolerance(double clipW, double wError, double wMin, double storage) const {
    const double u = 0x1p-24;
    const double s = scale_;
    const double a = 1.0 + constant_ * clipW;
    const double l = std::log2(a) * s;
    const double relativeA =
        constant_ * wError / a + (16.0 * std::max(clipW / wMin, 1.0) + 3.0) * u;
    return s * relativeA / std::numbers::ln2 + s * 0x1p-21 + 3.0 * 0x1p-23 * std::abs(l) +
           2.0 * u * std::abs(l) + (reversed_ ? u : 0.0) + storage;
  }

 private:
  double constant_;
  double far_;
  bool reversed_;
  double scale_;
};

// The mapping a camera's meshes are drawn with under a convention; nullopt: the projective depth.
inline std::optional<LogDepthMapping> logDepthMapping(const Camera& camera, DepthMode mode) {
  if (!camera.logarithmicDepth) return std::nullopt;
  return LogDepthMapping{camera.logarithmicDepth->constant, camera.logarithmicDepth->far,
                         mode.reversed};
}

}  // namespace clipray

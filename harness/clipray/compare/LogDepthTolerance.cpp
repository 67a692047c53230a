// The tolerance of a logarithmic depth written by the mesh shader (LogarithmicDepth.hpp): what
// the w the fragment interpolates may differ by from the exact hit's, from the triangle's clip
// vertices.

#include <algorithm>
#include <array>
#include <cmath>

#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/compare/ToleranceTerms.hpp"

namespace clipray {

using detail::divideTwo;
using detail::kInf;
using detail::kNaN;

ToleranceModel::LogDepthTerms ToleranceModel::logDepthTermsOf(std::uint32_t primitiveId) const {
  const std::array<glm::dvec3, 3> world = intersector_.worldTriangle(primitiveId);
  std::array<glm::dvec4, 3> clip;
  for (int k = 0; k < 3; ++k) clip[k] = setup_.clipFromWorld * glm::dvec4(world[k], 1.0);
  // 1 / w is affine in NDC x, y over the triangle's plane: a x_ndc + b y_ndc + c, which each
  // vertex satisfies as a x_i + b y_i + c w_i = 1 whatever the sign of its w.
  const glm::dmat3 rows(glm::dvec3(clip[0].x, clip[1].x, clip[2].x),
                        glm::dvec3(clip[0].y, clip[1].y, clip[2].y),
                        glm::dvec3(clip[0].w, clip[1].w, clip[2].w));
  const double det = glm::determinant(rows);
  if (det == 0.0) return {kInf, kInf};  // edge-on: no pixel of it is measurable
  const glm::dvec3 plane = glm::inverse(glm::transpose(rows)) * glm::dvec3(1.0);
  // d w / d pixel = -w^2 d(1 / w) / d x_ndc * (2 / viewport size): the factor besides w^2.
  const double wGradient =
      std::abs(plane.x) * 2.0 / viewport_.width + std::abs(plane.y) * 2.0 / viewport_.height;
  // The smallest w of the polygon the near plane leaves (further clipping only raises it).
  const double zn = setup_.mode.clipVolumeMinZ();
  double wMin = kInf;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec4& p = clip[k];
    const glm::dvec4& q = clip[(k + 1) % 3];
    const double dp = p.z - zn * p.w, dq = q.z - zn * q.w;
    if (dp >= 0.0) wMin = std::min(wMin, p.w);
    if ((dp < 0.0) != (dq < 0.0)) wMin = std::min(wMin, p.w + dp / (dp - dq) * (q.w - p.w));
  }
  if (!(wMin > 0.0) || !std::isfinite(wMin)) wMin = kNaN;
  return {wGradient, wMin};
}

double ToleranceModel::logDepthTolerance(std::uint32_t primitiveId, const glm::dvec4& hitClip,
                                         double storage) const {
  // The triangle's terms, built up front for the triangles the raster shows.
  const std::uint32_t slot = primitiveId < slotOfId_.size() ? slotOfId_[primitiveId] : kNoSlot;
  const LogDepthTerms terms = slot != kNoSlot ? logDepthTerms_[slot] : logDepthTermsOf(primitiveId);
  if (terms.wGradient == kInf) return kInf;  // edge-on
  const double w = hitClip.w;
  const double gradient = w * w * terms.wGradient;
  // How far the triangle may move under the pixel centre: the subpixel snap plus the float
  // transform's x, y error in pixels (as triangleDepthTolerance).
  const glm::dvec4& bound = pixelTerms(primitiveId).clipErrorBound;
  const auto [xNdc, yNdc] = divideTwo(hitClip.x, w, hitClip.y, w);
  const double xyErrorPixels =
      std::max((bound.x + std::abs(xNdc) * bound.w) * 0.5 * viewport_.width,
               (bound.y + std::abs(yNdc) * bound.w) * 0.5 * viewport_.height) /
      std::abs(w);
  const double wError = bound.w + gradient * (subpixelStep_ + xyErrorPixels);
  return setup_.logDepth->tolerance(w, wError, std::isnan(terms.wMin) ? w : terms.wMin, storage);
}

}  // namespace clipray

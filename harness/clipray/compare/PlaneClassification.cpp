// The classification of a pixel the screen path decided from its triangle's planes
// (AnalyticFrame::planesById): the hit's NDC depth and reciprocal clip w evaluated at the pixel
// centre, in place of a ray, its watertight t and the matrix product of the hit point.
//
// The figures are the ray path's (PixelClassification.cpp) with the hit's clip coordinates
// (x w, y w, z w, w) at the pixel centre's NDC (x, y), z and 1 / w from the planes. The distance
// along the line of sight to where the raster's depth lies, relative to the distance from the eye:
// along the line through the eye E and the hit P, clip coordinates are (1 - s) M E + s M P with
// M E = (0, 0, c, 0) (c: the eye's clip z), so the point at NDC depth z_r has
// s = c / (c + w_P (z_r - z_P)), and its distance from the eye over the hit's is s:
// |s - 1| = |z_P - z_r| / |c / w_P + z_r - z_P|. A parallel camera's NDC depth is affine in the
// distance along its rays, which span the depth of view: |z_P - z_r| / |z_far - z_near|.
//
// The class must be the ray path's. Both paths' inputs lie within tiny bounds of the exact
// crossing (the planes' certified bounds, ScreenTriangleSetup.cpp; the ray path's t within
// rounding of it), so their depths differ by at most twice the plane's bound and their tolerances
// by far less than 2^-20 of themselves (each term is a product or quotient of those inputs). A
// pixel whose error lies within that much of its tolerance, or whose depth lies that close to a
// change of the float depth's quantum, is left to the ray path; so is any pixel whose two sides
// show different primitives.

#include <cmath>
#include <limits>

#include "clipray/compare/PixelClassification.hpp"
#include "clipray/compare/ToleranceTerms.hpp"

namespace clipray::detail {

bool FrameClassifier::classifyFromPlanes(std::size_t i, double xNdc, double yNdc,
                                         RunMetrics& metrics, WorkerSamples& samples) const {
  const std::uint32_t id = analytic_.hits[i].primitiveId;
  if (raster_.ids[i] != id) return false;
  const std::uint32_t slot = model_.slotOfId_[id];
  if (slot == ToleranceModel::kNoSlot) return false;
  const TrianglePlanes& p = (*planes_)[id];
  const double zNdc = p.za * xNdc + (p.zb * yNdc + p.zc);
  const double reciprocalW = p.ra * xNdc + (p.rb * yNdc + p.rc);
  if (!(reciprocalW > 0.0) || !std::isfinite(zNdc + reciprocalW)) return false;

  const double depth = planeMapping_.windowDepth(zNdc);
  const double rasterDepth = raster_.depth[i];
  const double error = std::abs(rasterDepth - depth);
  const double quantum = quantumAt(setup_.depthFormat, depth);
  const double toWindow = model_.windowFromNdcScale_;
  const double tolerance =
      triangleDepthToleranceAtNdc(model_.pixelTerms_[slot], xNdc, yNdc, zNdc, reciprocalW, depth,
                                  quantum, toWindow, model_.subpixelStep_, raster_.viewport);
  // Certain: the error clear of the tolerance by both depths' reach and the tolerance's spread,
  // and one float quantum over the depths' reach.
  const double reach = 2.0 * p.depthError * toWindow;
  if (!(std::abs(error - tolerance) > reach + 0x1p-20 * tolerance)) return false;
  if (setup_.depthFormat == DepthFormat::Float32) {
    const double span = reach + 0x1p-40 * std::abs(depth);
    if (quantumAt(DepthFormat::Float32, depth - span) !=
        quantumAt(DepthFormat::Float32, depth + span)) {
      return false;
    }
  }

  const double zRaster = planeMapping_.ndcOfWindowDepth(rasterDepth);
  const double apart = std::abs(zNdc - zRaster);
  const double relative =
      parallel_ ? apart / depthSpan_ : apart / std::abs(eyeClipZ_ * reciprocalW + zRaster - zNdc);
  const double ratio = error / tolerance;
  const double quanta = error / quantum;

  ++metrics.rasterHits;
  ++metrics.rayHits;
  ++metrics.depthCompared;
  pixels_.rasterDepth[i] = raster_.depth[i];
  pixels_.analyticDepth[i] = depth;
  pixels_.toleranceRatio[i] = static_cast<float>(ratio);
  KindSamples& kind = samplesOf(samples, 0);
  kind.quanta.push_back(quanta);
  kind.relative.push_back(relative);
  kind.ratios.push_back(ratio);
  const bool beyond = !(ratio <= 1.0);  // NaN counts as beyond tolerance
  metrics.depthBeyondTolerance += beyond ? 1 : 0;
  pixels_.classes[i] = beyond ? PixelClass::DepthBeyondTolerance : PixelClass::Agree;
  return true;
}

}  // namespace clipray::detail

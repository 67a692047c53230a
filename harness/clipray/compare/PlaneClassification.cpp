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
// A logarithmic depth (LogarithmicDepth.hpp) is L(w) of the hit's w = 1 / (1 / w from the plane),
// and since w is 0 at the eye and affine along a sight line, the distance figure is
// |w_r - w_P| / w_P with w_r the w whose L is the raster's depth.
//
// The class must be the ray path's. Both paths' inputs lie within tiny bounds of the exact
// crossing (the planes' certified bounds, ScreenTriangleSetup.cpp; the ray path's t within
// rounding of it), so their depths differ by at most twice the plane's bound and their tolerances
// by far less than 2^-20 of themselves (each term is a product or quotient of those inputs). A
// pixel whose error lies within that much of its tolerance, or whose depth lies that close to a
// change of the float depth's quantum, is left to the ray path; so is any pixel whose two sides
// show different primitives.

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "clipray/compare/PixelClassification.hpp"
#include "clipray/compare/PolygonOffset.hpp"
#include "clipray/compare/ToleranceTerms.hpp"
#include "clipray/util/KernelChoice.hpp"

namespace clipray::detail {

namespace {

// Four doubles, four lane masks and four floats in GCC's vector extensions: the four-pixel kernel
// below compiles to AVX2 inside fourFromPlanesAvx2 and to pairs of SSE2 operations elsewhere, with
// the scalar kernel's operations in its order and no fused multiply-add, so the same bits.
using Lanes = double __attribute__((vector_size(32)));
using Mask = long long __attribute__((vector_size(32)));
using Floats = float __attribute__((vector_size(16)));
using FloatBits = unsigned __attribute__((vector_size(16)));

// The helpers and the kernel below pass lanes by value, whose ABI differs with and without AVX;
// they are always inlined (no call, so no ABI), and GCC's note on it (given where the file ends)
// is silenced for this file.
#pragma GCC diagnostic ignored "-Wpsabi"
[[gnu::always_inline]] inline Lanes load(const double* p) {
  Lanes lanes;
  std::memcpy(&lanes, p, sizeof lanes);
  return lanes;
}
// std::abs per lane: the sign bit cleared (-0.0 too, as std::abs clears it).
[[gnu::always_inline]] inline Lanes absolute(const Lanes& v) {
  Mask bits;
  std::memcpy(&bits, &v, sizeof bits);
  bits &= 0x7fffffffffffffffLL;
  Lanes magnitude;
  std::memcpy(&magnitude, &bits, sizeof magnitude);
  return magnitude;
}
[[gnu::always_inline]] inline Lanes largerOf(const Lanes& a, const Lanes& b) {
  return a < b ? b : a;  // std::max(a, b)
}

// quantumAt for a float depth buffer, per lane; false where a lane's |depth| rounds to no finite
// float (the scalar path asks depthQuantum there).
[[gnu::always_inline]] inline bool floatQuanta(const Lanes& depth, Lanes& quantum) {
  const Floats d = __builtin_convertvector(absolute(depth), Floats);
  FloatBits bits;
  std::memcpy(&bits, &d, sizeof bits);
  const FloatBits beyond = bits >= 0x7f800000u;
  if ((beyond[0] | beyond[1] | beyond[2] | beyond[3]) != 0) return false;
  const FloatBits nextBits = bits + 1u;
  Floats next;
  std::memcpy(&next, &nextBits, sizeof next);
  quantum = largerOf(__builtin_convertvector(next - d, Lanes),
                     Lanes{} + static_cast<double>(std::numeric_limits<float>::min()));
  return true;
}

// A field of the four pixels' planes or terms: one load where all four show one triangle.
[[gnu::always_inline]] inline Lanes planeField(const FourPlanePixels& p,
                                               double TrianglePlanes::*field) {
  if (p.one) return Lanes{} + p.planes[0]->*field;
  return Lanes{p.planes[0]->*field, p.planes[1]->*field, p.planes[2]->*field, p.planes[3]->*field};
}
[[gnu::always_inline]] inline Lanes boundField(const FourPlanePixels& p, int k) {
  if (p.one) return Lanes{} + (*p.clipErrorBound[0])[k];
  return Lanes{(*p.clipErrorBound[0])[k], (*p.clipErrorBound[1])[k], (*p.clipErrorBound[2])[k],
               (*p.clipErrorBound[3])[k]};
}
[[gnu::always_inline]] inline Lanes termField(const FourPlanePixels& p,
                                              const double* const (&field)[4]) {
  if (p.one) return Lanes{} + *field[0];
  return Lanes{*field[0], *field[1], *field[2], *field[3]};
}

[[gnu::always_inline]] inline bool fourFromPlanes(const PlaneFrameConstants& in,
                                                  const FourPlanePixels& p, FourPlaneFigures& out) {
  const Lanes x = load(p.xNdc), y = Lanes{} + p.yNdc;
  const Lanes zNdc = planeField(p, &TrianglePlanes::za) * x +
                     (planeField(p, &TrianglePlanes::zb) * y + planeField(p, &TrianglePlanes::zc));
  const Lanes reciprocalW =
      planeField(p, &TrianglePlanes::ra) * x +
      (planeField(p, &TrianglePlanes::rb) * y + planeField(p, &TrianglePlanes::rc));
  const Mask usable = (reciprocalW > 0.0) & (absolute(zNdc) < kInf) & (reciprocalW < kInf);
  if ((usable[0] & usable[1] & usable[2] & usable[3]) == 0) return false;
  // The object's depth range where objects have their own: n + (f - n) d.
  Lanes depth = (zNdc - in.zn) * in.toWindowDepth;
  Lanes toWindow = Lanes{} + in.toWindow;
  if (in.objectRanges) {
    depth = load(p.rangeLow) + load(p.rangeSpan) * depth;
    toWindow = toWindow * absolute(load(p.rangeSpan));
  }
  Floats rasterFloats;
  std::memcpy(&rasterFloats, p.rasterDepth, sizeof rasterFloats);
  const Lanes rasterDepth = __builtin_convertvector(rasterFloats, Lanes);
  const Lanes reach = 2.0 * planeField(p, &TrianglePlanes::depthError) * toWindow;
  // Depth clamp: clear of the range's ends by the reach (else it may be clamped).
  const Mask inRange = (depth - reach > in.clampLow) & (depth + reach < in.clampHigh);
  if ((inRange[0] & inRange[1] & inRange[2] & inRange[3]) == 0) return false;
  // A polygon offset's band (offsetBand, clamped to [0, 1] in a fixed-point buffer): its middle
  // and half width move by at most as much as the depth, so the tolerance by the reach too.
  Lanes compared = depth, halfWidth = Lanes{}, toleranceReach = Lanes{};
  if (in.offsets) {
    Lanes low = depth + load(p.offsetLow), high = depth + load(p.offsetHigh);
    if (in.fixedQuantum != 0.0) {
      const Lanes zero = Lanes{}, one = Lanes{} + 1.0;
      low = low < zero ? zero : (low > one ? one : low);
      high = high < zero ? zero : (high > one ? one : high);
    }
    compared = 0.5 * (low + high);
    halfWidth = 0.5 * (high - low);
    toleranceReach = reach;
  }
  const Lanes error = absolute(rasterDepth - compared);
  Lanes quantum = Lanes{} + in.fixedQuantum;
  if (in.fixedQuantum == 0.0) {
    // One float quantum over the depths' reach (else the ray path decides). The quantum grows
    // with |depth|: where the reach stays above 0, the depth's quantum is the one at either end.
    const Lanes span = reach + 0x1p-40 * absolute(compared);
    Lanes below, above;
    if (!floatQuanta(compared - span, below) || !floatQuanta(compared + span, above)) {
      return false;
    }
    const Mask steady = below == above;
    if ((steady[0] & steady[1] & steady[2] & steady[3]) == 0) return false;
    const Mask positive = compared - span > 0.0;
    if ((positive[0] & positive[1] & positive[2] & positive[3]) != 0) {
      quantum = below;
    } else if (!floatQuanta(compared, quantum)) {
      return false;
    }
  }
  const double u = kFloatUnitRoundoff;
  const Lanes boundW = boundField(p, 3);
  const Lanes xyError = largerOf((boundField(p, 0) + absolute(x) * boundW) * 0.5 * in.width,
                                 (boundField(p, 1) + absolute(y) * boundW) * 0.5 * in.height);
  const Lanes vertex = (boundField(p, 2) + absolute(zNdc) * boundW) * reciprocalW * toWindow +
                       2.0 * u * absolute(depth);
  const Lanes snap = termField(p, p.gradient) * (in.subpixelStep + xyError * reciprocalW);
  const Lanes tolerance = halfWidth + (quantum + vertex + snap + termField(p, p.interpolation));
  const Mask certain = absolute(error - tolerance) > reach + toleranceReach + 0x1p-20 * tolerance;
  if ((certain[0] & certain[1] & certain[2] & certain[3]) == 0) return false;
  // The raster's depth less the offset's move, in the object's range, back to NDC.
  Lanes unmoved = in.offsets ? rasterDepth - (compared - depth) : rasterDepth;
  if (in.objectRanges) unmoved = (unmoved - load(p.rangeLow)) / load(p.rangeSpan);
  const Lanes zRaster = unmoved * (1.0 - in.zn) + in.zn;
  const Lanes apart = absolute(zNdc - zRaster);
  const Lanes relative = in.parallel ? apart / in.depthSpan
                                     : apart / absolute(in.eyeClipZ * reciprocalW + zRaster - zNdc);
  const Lanes ratio = error / tolerance, quanta = error / quantum;
  std::memcpy(out.depth, &depth, sizeof depth);
  std::memcpy(out.ratio, &ratio, sizeof ratio);
  std::memcpy(out.quanta, &quanta, sizeof quanta);
  std::memcpy(out.relative, &relative, sizeof relative);
  return true;
}

bool fourFromPlanesPortable(const PlaneFrameConstants& in, const FourPlanePixels& p,
                            FourPlaneFigures& out) {
  return fourFromPlanes(in, p, out);
}

#if defined(__x86_64__) || defined(__i386__)
// AVX2 without FMA: GCC contracts a * b + c into a fused multiply-add wherever the target has
// one (C++ is not contract-off by default), which would round differently from the baseline.
__attribute__((target("avx2"))) bool fourFromPlanesAvx2(const PlaneFrameConstants& in,
                                                        const FourPlanePixels& p,
                                                        FourPlaneFigures& out) {
  return fourFromPlanes(in, p, out);
}
#endif

}  // namespace

bool FrameClassifier::classifyFromPlanes(std::size_t i, double xNdc, double yNdc,
                                         RunMetrics& metrics, WorkerSamples& samples) const {
  const std::uint32_t id = analytic_.hits[i].primitiveId;
  if (raster_.ids[i] != id) return false;
  const std::uint32_t slot = model_.slotOfId_[id];
  if (slot == ToleranceModel::kNoSlot) return false;
  const TrianglePlanes& p = (*planes_)[id];
  const double zNdc = p.za * xNdc + (p.zb * yNdc + p.zc);
  const double reciprocalW = p.ra * xNdc + (p.rb * yNdc + p.rc);
  if (!(reciprocalW > 0.0) || !std::isfinite(zNdc) || !std::isfinite(reciprocalW)) return false;
  const double rasterDepth = raster_.depth[i];
  PlaneFigures figures;
  const bool found = setup_.logDepth
                         ? logDepthFromPlanes(p, id, xNdc, yNdc, reciprocalW, rasterDepth, figures)
                         : projectiveDepthFromPlanes(p, id, slot, xNdc, yNdc, zNdc, reciprocalW,
                                                     rasterDepth, figures);
  if (!found) return false;
  // Certain: the error clear of the tolerance by both depths' reach and the tolerance's spread,
  // and one float quantum over the depths' reach.
  const double error = std::abs(rasterDepth - figures.compared);
  if (!(std::abs(error - figures.tolerance) >
        figures.reach + figures.toleranceReach + 0x1p-20 * figures.tolerance)) {
    return false;
  }
  if (setup_.depthFormat == DepthFormat::Float32) {
    const double span = figures.reach + 0x1p-40 * std::abs(figures.compared);
    if (quantumAt(DepthFormat::Float32, figures.compared - span) !=
        quantumAt(DepthFormat::Float32, figures.compared + span)) {
      return false;
    }
  }
  const double ratio = error / figures.tolerance;
  const double quanta = error / figures.quantum;

  ++metrics.rasterHits;
  ++metrics.rayHits;
  ++metrics.depthCompared;
  ++metrics.planePixels.fromPlanes;
  pixels_.rasterDepth[i] = raster_.depth[i];
  pixels_.analyticDepth[i] = figures.depth;
  pixels_.toleranceRatio[i] = static_cast<float>(ratio);
  KindSamples& kind = samplesOf(samples, 0);
  kind.quanta.push_back(quanta);
  kind.relative.push_back(figures.relative);
  kind.ratios.push_back(ratio);
  const bool beyond = !(ratio <= 1.0);  // NaN counts as beyond tolerance
  metrics.depthBeyondTolerance += beyond ? 1 : 0;
  pixels_.classes[i] = beyond ? PixelClass::DepthBeyondTolerance : PixelClass::Agree;
  return true;
}

bool FrameClassifier::projectiveDepthFromPlanes(const TrianglePlanes& p, std::uint32_t id,
                                                std::uint32_t slot, double xNdc, double yNdc,
                                                double zNdc, double reciprocalW, double rasterDepth,
                                                PlaneFigures& out) const {
  // The object's own depth range, if it has one.
  const bool ownRange = !setup_.oneDepthRange();
  const DepthMapping mapping = ownRange ? setup_.depthMappingOf(id) : planeMapping_;
  const double toWindow = ownRange ? mapping.windowFromNdcScale() : model_.windowFromNdcScale_;
  // Under depth clamp, the depth before the clamp, clear of the range's ends by the planes' reach
  // (else it may be clamped: the ray path decides).
  const double depth = mapping.mappedWindowDepth(zNdc);
  const double reach = 2.0 * p.depthError * toWindow;
  if (!(depth - reach > planeConstants_.clampLow && depth + reach < planeConstants_.clampHigh)) {
    return false;
  }
  // A polygon offset: compared with the middle of the depths GL allows, the tolerance widened by
  // their half width (PolygonOffset.hpp); both move by at most as much as the depth.
  const OffsetBand band = setup_.objectOffsets.empty()
                              ? OffsetBand{depth, 0.0}
                              : offsetBand(model_.offsetInterval(id), depth, setup_.depthFormat);
  const double quantum = quantumAt(setup_.depthFormat, band.middle);
  const double tolerance =
      band.halfWidth + triangleDepthToleranceAtNdc(model_.pixelTerms_[slot], xNdc, yNdc, zNdc,
                                                   reciprocalW, depth, quantum, toWindow,
                                                   model_.subpixelStep_, raster_.viewport);
  const double zRaster = mapping.ndcOfWindowDepth(rasterDepth - (band.middle - depth));
  const double apart = std::abs(zNdc - zRaster);
  const double relative =
      parallel_ ? apart / planeConstants_.depthSpan
                : apart / std::abs(planeConstants_.eyeClipZ * reciprocalW + zRaster - zNdc);
  out = {depth,   band.middle, tolerance,
         quantum, reach,       setup_.objectOffsets.empty() ? 0.0 : reach,
         relative};
  return true;
}

bool FrameClassifier::logDepthFromPlanes(const TrianglePlanes& p, std::uint32_t id, double xNdc,
                                         double yNdc, double reciprocalW, double rasterDepth,
                                         PlaneFigures& out) const {
  const LogDepthMapping& mapping = *setup_.logDepth;
  // Both paths' 1 / w lie within the plane's bound of the exact crossing's (as their NDC z lie
  // within the depth plane's): the ray path's within twice the bound of the plane's.
  const double w = 1.0 / reciprocalW;
  const double depth = mapping.windowDepth(w);
  const std::optional<LogDepthMapping::Reach> reach =
      mapping.reachOver(reciprocalW, 2.0 * p.reciprocalWError, depth);
  if (!reach) return false;
  // The tolerance reads w through w^2, w / w_min and 1 + C w: over so narrow a range of w its
  // spread stays below 2^-21 of itself (within the 2^-20 the certainty test allows).
  if (!((reach->wHigh - reach->wLow) < 0x1p-24 * reach->wLow)) return false;
  const double quantum = quantumAt(setup_.depthFormat, depth);
  const double tolerance =
      model_.logDepthTolerance(id, glm::dvec4(xNdc * w, yNdc * w, 0.0, w), quantum);
  // The distance from the eye along a sight line is proportional to clip w (0 at the eye): the
  // raster's relative to the hit's, as the ray path measures it along the ray.
  const double relative = std::abs(mapping.clipWOfWindowDepth(rasterDepth) - w) / w;
  out = {depth, depth, tolerance, quantum, reach->depth, 0.0, relative};
  return true;
}

bool FrameClassifier::classifyFourFromPlanes(std::size_t first, const double* xNdc, double yNdc,
                                             RunMetrics& metrics, WorkerSamples& samples) const {
  const std::uint32_t* rasterIds = &raster_.ids[first];
  const Hit* hits = &analytic_.hits[first];
  FourPlanePixels p;
  std::uint32_t previousId = 0;
  for (std::size_t l = 0; l < 4; ++l) {
    const std::uint32_t id = hits[l].primitiveId;
    if (id == 0 || rasterIds[l] != id || !std::isnan(hits[l].t)) return false;
    // Neighbouring pixels mostly show one triangle: its planes and terms are looked up once.
    if (id != previousId) {
      const std::uint32_t slot = model_.slotOfId_[id];
      if (slot == ToleranceModel::kNoSlot) return false;
      const ToleranceModel::PixelTerms& terms = model_.pixelTerms_[slot];
      p.planes[l] = &(*planes_)[id];
      p.clipErrorBound[l] = &terms.clipErrorBound;
      p.gradient[l] = &terms.gradient;
      p.interpolation[l] = &terms.interpolation;
      const glm::dvec2 range = planeConstants_.objectRanges
                                   ? setup_.objectDepthRanges.rangeOf(id, setup_.depthRange)
                                   : setup_.depthRange;
      p.rangeLow[l] = range.x;
      p.rangeSpan[l] = range.y - range.x;
      const OffsetInterval offset =
          planeConstants_.offsets ? model_.offsetInterval(id) : OffsetInterval{};
      p.offsetLow[l] = offset.low;
      p.offsetHigh[l] = offset.high;
      previousId = id;
    } else {
      p.planes[l] = p.planes[l - 1];
      p.clipErrorBound[l] = p.clipErrorBound[l - 1];
      p.gradient[l] = p.gradient[l - 1];
      p.interpolation[l] = p.interpolation[l - 1];
      p.rangeLow[l] = p.rangeLow[l - 1];
      p.rangeSpan[l] = p.rangeSpan[l - 1];
      p.offsetLow[l] = p.offsetLow[l - 1];
      p.offsetHigh[l] = p.offsetHigh[l - 1];
    }
  }
  p.one = hits[0].primitiveId == hits[3].primitiveId &&
          hits[1].primitiveId == hits[3].primitiveId && hits[2].primitiveId == hits[3].primitiveId;
  p.xNdc = xNdc;
  p.yNdc = yNdc;
  p.rasterDepth = &raster_.depth[first];
  FourPlaneFigures figures;
#if defined(__x86_64__) || defined(__i386__)
  const bool done = fourPlanesAvx2_ ? fourFromPlanesAvx2(planeConstants_, p, figures)
                                    : fourFromPlanesPortable(planeConstants_, p, figures);
#else
  const bool done = fourFromPlanesPortable(planeConstants_, p, figures);
#endif
  if (!done) return false;
  // The four pixels' figures and images, as classifyFromPlanes writes them one by one.
  KindSamples& kind = samplesOf(samples, 0);
  metrics.rasterHits += 4;
  metrics.rayHits += 4;
  metrics.depthCompared += 4;
  metrics.planePixels.fromPlanes += 4;
  appendFour(kind.quanta, figures.quanta);
  appendFour(kind.relative, figures.relative);
  appendFour(kind.ratios, figures.ratio);
  std::memcpy(&pixels_.rasterDepth[first], &raster_.depth[first], 4 * sizeof(float));
  std::memcpy(&pixels_.analyticDepth[first], figures.depth, 4 * sizeof(double));
  for (std::size_t l = 0; l < 4; ++l) {
    const std::size_t i = first + l;
    pixels_.toleranceRatio[i] = static_cast<float>(figures.ratio[l]);
    const bool beyond = !(figures.ratio[l] <= 1.0);  // NaN counts as beyond tolerance
    metrics.depthBeyondTolerance += beyond ? 1 : 0;
    pixels_.classes[i] = beyond ? PixelClass::DepthBeyondTolerance : PixelClass::Agree;
  }
  return true;
}

}  // namespace clipray::detail

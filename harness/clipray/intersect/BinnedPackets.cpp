// The screen-bin walk of the packet kernels: a tile's packet checks that its rays stay on their
// pixel centres' lines of sight, then tests only the triangles binned in the tile (FrameBins),
// skipping those behind every lane's current hit. The hits are the BVH walk's, bit for bit:
// the bins only leave out triangles no ray of the tile can hit.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "clipray/intersect/Packet.hpp"

#if CLIPRAY_HAVE_AVX2_KERNELS

namespace clipray::detail::packet {

namespace {

// The pixel check is a bound, not a result that must match the scalar code: it may fuse its
// multiplies and adds (fewer roundings, so its error analysis still holds).
#define CLIPRAY_AVX2_FMA __attribute__((target("avx2,fma")))

// One row of a matrix: its x, y, z factors and translation, broadcast.
struct WideRow {
  __m256d x, y, z, translation;
};

CLIPRAY_AVX2 inline WideRow wideRow(const glm::dmat4& m, int r, bool withTranslation) {
  return {bcast(m[0][r]), bcast(m[1][r]), bcast(m[2][r]), bcast(withTranslation ? m[3][r] : 0.0)};
}

// The row applied to (x, y, z, 1).
CLIPRAY_AVX2_FMA inline __m256d applyRow(const WideRow& row, __m256d x, __m256d y, __m256d z) {
  return _mm256_fmadd_pd(row.x, x,
                         _mm256_fmadd_pd(row.y, y, _mm256_fmadd_pd(row.z, z, row.translation)));
}

// |x - cx w| <= epsX w and |y - cy w| <= epsY w: the homogeneous point projects near (cx, cy).
CLIPRAY_AVX2_FMA inline __m256d nearCentre(__m256d x, __m256d y, __m256d w, __m256d cx, __m256d cy,
                                           __m256d epsX, __m256d epsY, __m256d signBit) {
  const __m256d offX = _mm256_andnot_pd(signBit, _mm256_fnmadd_pd(cx, w, x));
  const __m256d offY = _mm256_andnot_pd(signBit, _mm256_fnmadd_pd(cy, w, y));
  return _mm256_and_pd(_mm256_cmp_pd(offX, _mm256_mul_pd(epsX, w), _CMP_LE_OQ),
                       _mm256_cmp_pd(offY, _mm256_mul_pd(epsY, w), _CMP_LE_OQ));
}

// The largest clip w at which a hit could still win in each lane of group g: w of the current best
// hit (w at tMax before any), or of the origin when w falls along the ray, widened by 2^-20 of
// itself -- far more than the rounding of the watertight t (a triangle skipped by this bound
// cannot produce an accepted hit). +inf when that w is not a number (an infinite far plane with
// w constant along the ray).
CLIPRAY_AVX2 inline __m256d groupReach(const Packet& p, int g) {
  const int base = g * 4;
  const __m256d w0 = _mm256_load_pd(p.wOrigin + base);
  const __m256d atBest = _mm256_add_pd(
      w0, _mm256_mul_pd(_mm256_load_pd(p.bestT + base), _mm256_load_pd(p.wSlope + base)));
  const __m256d finiteReach =
      _mm256_blendv_pd(atBest, bcast(std::numeric_limits<double>::infinity()),
                       _mm256_cmp_pd(atBest, atBest, _CMP_UNORD_Q));
  return _mm256_mul_pd(_mm256_max_pd(finiteReach, w0), bcast(1.0 + 0x1p-20));
}

// The largest groupReach over the packet's lanes.
CLIPRAY_AVX2 double packetReach(const Packet& p) {
  __m256d reach = groupReach(p, 0);
  for (int g = 1; g < p.lanes / 4; ++g) reach = _mm256_max_pd(reach, groupReach(p, g));
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, reach);
  return std::max(std::max(lanes[0], lanes[1]), std::max(lanes[2], lanes[3]));
}

}  // namespace

// Whether the packet's first `used` rays (before preparePacket: p.inv holds directions) stay on
// their pixel centres' lines of sight, so that the bins hold every triangle they can hit.
// With e0 = clip(origin), ed = clip(direction, w = 0) and e1 = e0 + tMax ed (ed when tMax is
// infinite), every point of the ray is a non-negative combination of e0 and e1. If both have
// w >= wClip (an infinite ray's ed: w >= 0) and both lie within kRayTolerancePx of the centre c
// (|x - c_x w| <= eps w), so does every point, and every hit point has w >= wClip.
// The test is trusted only where its rounding is below kMarginPx / 4: every quantity in it is
// off by at most 2^-49 of mag = (|row x or y| + 2 |row w|) applied to |e| (the bins' padding
// leaves kMarginPx), bounded through the rows' 1-norms R, the translations T and the largest
// |coordinate| of origin and direction: mag(e0) <= R max|o| + T, mag(e1) <= mag(e0) + tMax R
// max|d| (R max|d| for an infinite ray). A lane whose endpoint w is below 2^-49 mag / (margin
// in clip units) fails the check (its tile walks the BVH).
// scanOrder: the packet is the whole 8x8 tile in scan order (lane = 8 y + x), so its centres come
// straight from the tile's columns and rows.
CLIPRAY_AVX2_FMA bool raysOnTheirPixels(Packet& p, int used, bool scanOrder, const FrameBins& bins,
                                        int tileX, int tileY) {
  const glm::dmat4& m = bins.clipFromRelative();
  const Viewport viewport = bins.viewport();
  const double scaleX = 2.0 / viewport.width, scaleY = 2.0 / viewport.height;
  // NDC of the pixel centres: (2i + 1) / W - 1, for the tile's eight columns and rows, then per
  // lane.
  double columnX[FrameBins::kTile], rowY[FrameBins::kTile];
  for (int k = 0; k < FrameBins::kTile; ++k) {
    columnX[k] = (2.0 * (tileX * FrameBins::kTile + k) + 1.0) * (0.5 * scaleX) - 1.0;
    rowY[k] = (2.0 * (tileY * FrameBins::kTile + k) + 1.0) * (0.5 * scaleY) - 1.0;
  }
  alignas(32) double centreX[kMax], centreY[kMax];
  if (!scanOrder) {
    for (int l = 0; l < p.lanes; ++l) {
      centreX[l] = columnX[p.laneX[l]];
      centreY[l] = rowY[p.laneY[l]];
    }
  }
  const __m256d epsX = bcast(FrameBins::kRayTolerancePx * scaleX);
  const __m256d epsY = bcast(FrameBins::kRayTolerancePx * scaleY);
  const auto rowNorm = [&](int r) {
    return std::abs(m[0][r]) + std::abs(m[1][r]) + std::abs(m[2][r]);
  };
  const __m256d norm = bcast(std::max(rowNorm(0), rowNorm(1)) + 2.0 * rowNorm(3));
  const __m256d translation =
      bcast(std::max(std::abs(m[3][0]), std::abs(m[3][1])) + 2.0 * std::abs(m[3][3]));
  // w must exceed mag times this: 2^-49 / (kMarginPx / 4 in clip units).
  const __m256d roundingPerW =
      bcast(0x1p-49 / (0.25 * FrameBins::kMarginPx * std::min(scaleX, scaleY)));
  const __m256d wClip = bcast(bins.wClip());
  const __m256d zero = _mm256_setzero_pd();
  const __m256d infinity = bcast(std::numeric_limits<double>::infinity());
  const __m256d signBit = bcast(-0.0);
  const WideRow clipX = wideRow(m, 0, true), clipY = wideRow(m, 1, true),
                clipW = wideRow(m, 3, true);
  const WideRow slopeX = wideRow(m, 0, false), slopeY = wideRow(m, 1, false),
                slopeW = wideRow(m, 3, false);
  for (int base = 0; base < used; base += 4) {
    const __m256d ox = _mm256_load_pd(p.o[0] + base), oy = _mm256_load_pd(p.o[1] + base),
                  oz = _mm256_load_pd(p.o[2] + base);
    const __m256d dx = _mm256_load_pd(p.inv[0] + base), dy = _mm256_load_pd(p.inv[1] + base),
                  dz = _mm256_load_pd(p.inv[2] + base);
    const __m256d tMax = _mm256_load_pd(p.bestT + base);
    const __m256d e0x = applyRow(clipX, ox, oy, oz), e0y = applyRow(clipY, ox, oy, oz),
                  e0w = applyRow(clipW, ox, oy, oz);
    const __m256d edx = applyRow(slopeX, dx, dy, dz), edy = applyRow(slopeY, dx, dy, dz),
                  edw = applyRow(slopeW, dx, dy, dz);
    _mm256_store_pd(p.wOrigin + base, e0w);
    _mm256_store_pd(p.wSlope + base, edw);
    const __m256d finite = _mm256_cmp_pd(tMax, infinity, _CMP_LT_OQ);
    const __m256d e1x = _mm256_blendv_pd(edx, _mm256_fmadd_pd(tMax, edx, e0x), finite);
    const __m256d e1y = _mm256_blendv_pd(edy, _mm256_fmadd_pd(tMax, edy, e0y), finite);
    const __m256d e1w = _mm256_blendv_pd(edw, _mm256_fmadd_pd(tMax, edw, e0w), finite);
    const __m256d cx =
        scanOrder ? _mm256_loadu_pd(columnX + (base & 7)) : _mm256_load_pd(centreX + base);
    const __m256d cy = scanOrder ? bcast(rowY[base >> 3]) : _mm256_load_pd(centreY + base);
    const __m256d e1wOk = _mm256_blendv_pd(_mm256_cmp_pd(e1w, zero, _CMP_GE_OQ),
                                           _mm256_cmp_pd(e1w, wClip, _CMP_GE_OQ), finite);
    const __m256d maxO =
        _mm256_max_pd(_mm256_andnot_pd(signBit, ox),
                      _mm256_max_pd(_mm256_andnot_pd(signBit, oy), _mm256_andnot_pd(signBit, oz)));
    const __m256d maxD =
        _mm256_max_pd(_mm256_andnot_pd(signBit, dx),
                      _mm256_max_pd(_mm256_andnot_pd(signBit, dy), _mm256_andnot_pd(signBit, dz)));
    const __m256d mag0 = _mm256_fmadd_pd(norm, maxO, translation);
    const __m256d magD = _mm256_mul_pd(norm, maxD);
    const __m256d mag1 = _mm256_blendv_pd(magD, _mm256_fmadd_pd(tMax, magD, mag0), finite);
    const __m256d exact =
        _mm256_and_pd(_mm256_cmp_pd(_mm256_mul_pd(mag0, roundingPerW), e0w, _CMP_LE_OQ),
                      _mm256_cmp_pd(_mm256_mul_pd(mag1, roundingPerW), e1w, _CMP_LE_OQ));
    const __m256d ok = _mm256_and_pd(
        _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(e0w, wClip, _CMP_GE_OQ), e1wOk), exact),
        _mm256_and_pd(nearCentre(e0x, e0y, e0w, cx, cy, epsX, epsY, signBit),
                      nearCentre(e1x, e1y, e1w, cx, cy, epsX, epsY, signBit)));
    const int wanted = (1 << std::min(4, used - base)) - 1;
    if ((_mm256_movemask_pd(ok) & wanted) != wanted) return false;
  }
  return true;
}

// The triangles binned in the tile against the packet's groups: only the groups a triangle's
// half rows touch when the packet is the full 8x8 tile in scan order, and none once every lane's
// best hit lies nearer than the triangle's nearest w.
CLIPRAY_AVX2 void traceBins(const SceneIntersector& scene, const std::vector<Triangle>& triangles,
                            const FrameBins& bins, int tileX, int tileY, Packet& p,
                            bool groupsAreHalfRows, const Ray* rays) {
  const glm::dvec3 reference = scene.reference();
  const int groupCount = p.lanes / 4;
  const std::uint32_t allGroups = (1u << groupCount) - 1;
  for (int chunk = 0; chunk < bins.listChunkCount(); ++chunk) {
    for (const BinnedTriangle& entry : bins.list(chunk, tileX, tileY)) {
      // The triangles are scattered over the intersector's storage: start loading them now.
      const char* at = reinterpret_cast<const char*>(&triangles[entry.slot]);
      __builtin_prefetch(at);
      __builtin_prefetch(at + sizeof(Triangle) - 1);
    }
  }
  // The depth bound, for the whole tile: the largest reach over its lanes, refreshed every
  // kRefresh entries (hits only come nearer, so a stale bound is still a bound). Most tiles of a
  // mesh hold a few entries that all touch the nearest surface; a tile with many (several layers
  // of surfaces) skips those behind what its rays have already hit.
  constexpr int kRefresh = 8;
  double tileReach = std::numeric_limits<double>::infinity();
  int untilRefresh = kRefresh;
  for (int chunk = 0; chunk < bins.listChunkCount(); ++chunk) {
    for (const BinnedTriangle& entry : bins.list(chunk, tileX, tileY)) {
      if (--untilRefresh == 0) {
        tileReach = packetReach(p);
        untilRefresh = kRefresh;
      }
      if (static_cast<double>(entry.nearestW) > tileReach) continue;
      const std::uint32_t groups = groupsAreHalfRows ? entry.groupMask & allGroups : allGroups;
      if (groups == 0) continue;
      const Triangle& tri = triangles[entry.slot];
      const WideTriangle wt = wideTriangle(p, tri);
      for (std::uint32_t left = groups; left != 0; left &= left - 1) {
        testGroup(p, std::countr_zero(left), wt, tri, reference, rays);
      }
    }
  }
}
}  // namespace clipray::detail::packet

#endif

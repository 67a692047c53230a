#pragma once
// The packet of the AVX2 kernels (internal): up to SceneIntersector::kMaxPacket rays of one
// watertight permutation class as structure of arrays, and the watertight test of one triangle
// against four of its lanes. Shared by the BVH walk (PacketKernels.cpp) and the screen-bin walk
// (BinnedPackets.cpp); everything here gives the scalar code's bits (see PacketKernels.cpp).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "clipray/intersect/FrameBins.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/intersect/Watertight.hpp"

#if defined(__x86_64__) || defined(__i386__)
#define CLIPRAY_HAVE_AVX2_KERNELS 1
#include <immintrin.h>
#else
#define CLIPRAY_HAVE_AVX2_KERNELS 0
#endif

#if CLIPRAY_HAVE_AVX2_KERNELS

#define CLIPRAY_AVX2 __attribute__((target("avx2")))

namespace clipray::detail::packet {

inline constexpr std::size_t kMax = SceneIntersector::kMaxPacket;
inline constexpr double kNoId = 0x1p40;  // larger than any primitive id: "no hit yet"

struct alignas(32) Packet {
  double o[3][kMax];    // origin relative to the reference
  double inv[3][kMax];  // 1 / direction
  double shearX[kMax], shearY[kMax], shearZ[kMax];
  double bestT[kMax];
  double bestId[kMax];
  std::uint32_t rayIndex[kMax];
  std::uint8_t laneX[kMax], laneY[kMax];  // the lane's pixel within its tile
  // Binned packets only (raysOnTheirPixels): clip w of the origin and its rate along the ray.
  double wOrigin[kMax], wSlope[kMax];
  int lanes = 0;  // multiple of 4; padding lanes have bestT = -1 and never hit
  int kx = 0, ky = 0, kz = 0;
  // Packet bounds for the interval slab test; sign: +1 or -1 when all inverse directions on
  // the axis share it, 0 when they do not (the axis is then not used to cull).
  double oMin[3], oMax[3], invMin[3], invMax[3];
  int sign[3];
  // The same bounds laid out for slabPacket (lane k: axis k; lane 3 unused): the origin bound at
  // which each plane's distance is smallest (entry) or largest (exit), and which floats of the
  // node are the entry (indices 0-3) and exit (4-7) planes. useAxis: all ones where the axis
  // culls (its inverse directions share a sign and are finite).
  alignas(32) double oEnter[4], oExit[4], invLo[4], invHi[4];
  alignas(32) std::int64_t useAxis[4];
  alignas(32) std::int32_t planeIndex[8];
};

using Triangle = BvhTriangle;

// Keeps (t, id) when it is smaller than the lane's best: the scalar rule of closestHit.
inline void scalarLane(Packet& p, int lane, const WatertightRay& ray, const Triangle& tri) {
  const auto t = intersectTriangle(ray, p.bestT[lane], tri.a, tri.b, tri.c);
  if (!t) return;
  const double id = static_cast<double>(tri.primitiveId);
  if (*t < p.bestT[lane] || id < p.bestId[lane]) {
    p.bestT[lane] = *t;
    p.bestId[lane] = id;
  }
}

CLIPRAY_AVX2 inline __m256d bcast(double x) {
  return _mm256_set1_pd(x);
}

// A triangle's vertices in the packet's permuted axes (x: kx, y: ky, z: kz), broadcast once for
// all the groups that test it.
struct WideTriangle {
  __m256d ax, ay, az, bx, by, bz, cx, cy, cz, id;
};

CLIPRAY_AVX2 inline WideTriangle wideTriangle(const Packet& p, const Triangle& tri) {
  return {bcast(tri.a[p.kx]), bcast(tri.a[p.ky]),
          bcast(tri.a[p.kz]), bcast(tri.b[p.kx]),
          bcast(tri.b[p.ky]), bcast(tri.b[p.kz]),
          bcast(tri.c[p.kx]), bcast(tri.c[p.ky]),
          bcast(tri.c[p.kz]), bcast(static_cast<double>(tri.primitiveId))};
}

// The watertight test of one triangle against four lanes of the packet. Inlined into the loops: a
// call would spill the broadcast triangle and clear the upper halves of the registers (vzeroupper)
// for every group.
CLIPRAY_AVX2 __attribute__((always_inline)) inline void testGroup(Packet& p, int g,
                                                                  const WideTriangle& wt,
                                                                  const Triangle& tri,
                                                                  const glm::dvec3& reference,
                                                                  const Ray* rays) {
  const int base = g * 4;
  const __m256d okx = _mm256_load_pd(p.o[p.kx] + base);
  const __m256d oky = _mm256_load_pd(p.o[p.ky] + base);
  const __m256d okz = _mm256_load_pd(p.o[p.kz] + base);
  const __m256d sx = _mm256_load_pd(p.shearX + base);
  const __m256d sy = _mm256_load_pd(p.shearY + base);
  const __m256d Akz = _mm256_sub_pd(wt.az, okz);
  const __m256d Bkz = _mm256_sub_pd(wt.bz, okz);
  const __m256d Ckz = _mm256_sub_pd(wt.cz, okz);
  const __m256d ax = _mm256_add_pd(_mm256_sub_pd(wt.ax, okx), _mm256_mul_pd(sx, Akz));
  const __m256d ay = _mm256_add_pd(_mm256_sub_pd(wt.ay, oky), _mm256_mul_pd(sy, Akz));
  const __m256d bx = _mm256_add_pd(_mm256_sub_pd(wt.bx, okx), _mm256_mul_pd(sx, Bkz));
  const __m256d by = _mm256_add_pd(_mm256_sub_pd(wt.by, oky), _mm256_mul_pd(sy, Bkz));
  const __m256d cx = _mm256_add_pd(_mm256_sub_pd(wt.cx, okx), _mm256_mul_pd(sx, Ckz));
  const __m256d cy = _mm256_add_pd(_mm256_sub_pd(wt.cy, oky), _mm256_mul_pd(sy, Ckz));
  const __m256d u = _mm256_sub_pd(_mm256_mul_pd(cx, by), _mm256_mul_pd(cy, bx));
  const __m256d v = _mm256_sub_pd(_mm256_mul_pd(ax, cy), _mm256_mul_pd(ay, cx));
  const __m256d w = _mm256_sub_pd(_mm256_mul_pd(bx, ay), _mm256_mul_pd(by, ax));
  const __m256d zero = _mm256_setzero_pd();
  const __m256d anyNeg = _mm256_or_pd(
      _mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_LT_OQ), _mm256_cmp_pd(v, zero, _CMP_LT_OQ)),
      _mm256_cmp_pd(w, zero, _CMP_LT_OQ));
  const __m256d anyPos = _mm256_or_pd(
      _mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_GT_OQ), _mm256_cmp_pd(v, zero, _CMP_GT_OQ)),
      _mm256_cmp_pd(w, zero, _CMP_GT_OQ));
  const __m256d onEdge = _mm256_or_pd(
      _mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_EQ_OQ), _mm256_cmp_pd(v, zero, _CMP_EQ_OQ)),
      _mm256_cmp_pd(w, zero, _CMP_EQ_OQ));
  const __m256d inside =
      _mm256_andnot_pd(_mm256_and_pd(anyNeg, anyPos), _mm256_castsi256_pd(_mm256_set1_epi64x(-1)));
  const int edgeMask = _mm256_movemask_pd(onEdge);
  // No branch on whether a lane is inside: on the terrain two thirds of the groups the bins test
  // have one and the rest none, in no order a predictor can guess. t is computed for every lane
  // and kept where accepted.
  {
    const __m256d det = _mm256_add_pd(_mm256_add_pd(u, v), w);
    const __m256d sz = _mm256_load_pd(p.shearZ + base);
    const __m256d az = _mm256_mul_pd(sz, Akz);
    const __m256d bz = _mm256_mul_pd(sz, Bkz);
    const __m256d cz = _mm256_mul_pd(sz, Ckz);
    const __m256d tScaled = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(u, az), _mm256_mul_pd(v, bz)),
                                          _mm256_mul_pd(w, cz));
    const __m256d t = _mm256_div_pd(tScaled, det);
    const __m256d bestT = _mm256_load_pd(p.bestT + base);
    const __m256d bestId = _mm256_load_pd(p.bestId + base);
    const __m256d id = wt.id;
    const __m256d better = _mm256_or_pd(
        _mm256_cmp_pd(t, bestT, _CMP_LT_OQ),
        _mm256_and_pd(_mm256_cmp_pd(t, bestT, _CMP_EQ_OQ), _mm256_cmp_pd(id, bestId, _CMP_LT_OQ)));
    const __m256d valid = _mm256_and_pd(
        _mm256_and_pd(_mm256_cmp_pd(det, zero, _CMP_NEQ_OQ), _mm256_cmp_pd(t, zero, _CMP_GT_OQ)),
        _mm256_andnot_pd(onEdge, inside));
    const __m256d accept = _mm256_and_pd(valid, better);
    _mm256_store_pd(p.bestT + base, _mm256_blendv_pd(bestT, t, accept));
    _mm256_store_pd(p.bestId + base, _mm256_blendv_pd(bestId, id, accept));
  }
  if (edgeMask != 0) {
    for (int l = 0; l < 4; ++l) {
      if (!(edgeMask & (1 << l))) continue;
      const int lane = base + l;
      const Ray& ray = rays[p.rayIndex[lane]];
      scalarLane(p, lane, WatertightRay(ray.origin - reference, ray.direction), tri);
    }
  }
}

// The screen-bin walk (BinnedPackets.cpp).

// Whether the packet's first `used` rays (p.inv: their directions) stay on their pixel centres'
// lines of sight, so that the bins of tile (tileX, tileY) hold every triangle they can hit; also
// stores each lane's clip w at its origin and its rate along the ray (wOrigin, wSlope).
__attribute__((target("avx2,fma"))) bool raysOnTheirPixels(Packet& p, int used, bool scanOrder,
                                                           const FrameBins& bins, int tileX,
                                                           int tileY);
// The triangles binned in the tile against the packet's groups (after prepareShear).
CLIPRAY_AVX2 void traceBins(const SceneIntersector& scene, const std::vector<Triangle>& triangles,
                            const FrameBins& bins, int tileX, int tileY, Packet& p,
                            bool groupsAreHalfRows, const Ray* rays);

}  // namespace clipray::detail::packet

#endif

// Packet traversal for coherent rays (a tile of primary rays), bit-identical to closestHit's
// triangle part (SceneIntersector::closestHitsTile then adds the analytic primitives).
//
// Rays are grouped by their watertight axis permutation (kx, ky, kz); each group is one packet,
// stored as structure-of-arrays and processed four rays per AVX2 instruction. The BVH is walked
// once per packet:
// - every node: one interval-arithmetic slab test for the whole packet (origins and inverse
//   directions bounded per axis, the three axes in one AVX2 register), conservative by
//   construction, plus the packet's largest current best t;
// - leaves: an exact-or-wider slab test per group of four rays (all groups first, a bit mask of
//   those that may hit), then the watertight triangle test of Watertight.hpp for each such
//   group, operation for operation as the scalar code does it (separate multiplies and adds;
//   the AVX2 target has no FMA to contract into).
// The per-ray divisions (shear and inverse direction) are done four lanes at a time: IEEE
// division is correctly rounded, so they equal WatertightRay's.
// Hits keep the smallest (t, primitive id), so the visiting order never changes the answer; the
// rare lanes whose edge function is exactly zero take the scalar path for that triangle.
// A tile of a camera's own rays skips the BVH: BinnedPackets.cpp tests the triangles its screen
// bins list instead (the packet and the triangle test: Packet.hpp).

#include "clipray/intersect/PacketKernels.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

#include "clipray/intersect/Packet.hpp"
#include "clipray/intersect/Watertight.hpp"
#include "clipray/rays/FourRays.hpp"
#include "clipray/util/KernelChoice.hpp"

namespace clipray::detail {

#if CLIPRAY_HAVE_AVX2_KERNELS

namespace {

using namespace packet;  // the packet layout and the triangle test, shared with BinnedPackets.cpp

double maxAbs(const glm::dvec3& p) {
  return std::max(std::abs(p.x), std::max(std::abs(p.y), std::abs(p.z)));
}

// A leaf's box, broadcast once for all the groups of the packet.
struct WideBox {
  __m256d lower[3], upper[3];
};

CLIPRAY_AVX2 inline WideBox wideBox(const BvhNode& node) {
  WideBox box;
  for (int k = 0; k < 3; ++k) {
    box.lower[k] = bcast(static_cast<double>(node.lower[k]));
    box.upper[k] = bcast(static_cast<double>(node.upper[k]));
  }
  return box;
}

// Slab test of one box against four lanes: a bit per lane that may hit it before its best t.
CLIPRAY_AVX2 inline int slabGroup(const Packet& p, int g, const WideBox& box) {
  const int base = g * 4;
  __m256d tNear = _mm256_setzero_pd();
  __m256d tFar = _mm256_mul_pd(_mm256_load_pd(p.bestT + base), bcast(1.0 + 0x1p-30));
  for (int k = 0; k < 3; ++k) {
    const __m256d o = _mm256_load_pd(p.o[k] + base);
    const __m256d inv = _mm256_load_pd(p.inv[k] + base);
    const __m256d t0 = _mm256_mul_pd(_mm256_sub_pd(box.lower[k], o), inv);
    const __m256d t1 = _mm256_mul_pd(_mm256_sub_pd(box.upper[k], o), inv);
    // Directions have no zero component here (those rays take the scalar path): no NaN.
    tNear = _mm256_max_pd(tNear, _mm256_min_pd(t0, t1));
    tFar = _mm256_min_pd(tFar, _mm256_mul_pd(_mm256_max_pd(t0, t1), bcast(1.0 + 0x1p-40)));
  }
  return _mm256_movemask_pd(_mm256_cmp_pd(tNear, tFar, _CMP_LE_OQ));
}

// Interval slab test of a box against the whole packet, all three axes at once.
// (plane - o) * inv over o in [oMin, oMax], inv in [invMin, invMax] (one sign) has its extremes at
// the interval corners; rounding is monotone, so the corners of the rounded products are the
// extremes of every lane's rounded slab distance. For a fixed sign of inv the distance is monotone
// in o, so the smallest entry is at one origin bound and the largest exit at the other: two
// corners each. A NaN distance (only from non-finite node bounds) does not cull.
CLIPRAY_AVX2 inline bool slabPacket(const Packet& p, const BvhNode& node, double tLimit) {
  static_assert(sizeof(BvhNode) == 32);
  const __m256 raw = _mm256_loadu_ps(reinterpret_cast<const float*>(&node));
  const __m256 planes = _mm256_permutevar8x32_ps(
      raw, _mm256_load_si256(reinterpret_cast<const __m256i*>(p.planeIndex)));
  const __m256d enterPlane = _mm256_cvtps_pd(_mm256_castps256_ps128(planes));
  const __m256d exitPlane = _mm256_cvtps_pd(_mm256_extractf128_ps(planes, 1));
  const __m256d invLo = _mm256_load_pd(p.invLo);
  const __m256d invHi = _mm256_load_pd(p.invHi);
  const __m256d a = _mm256_sub_pd(enterPlane, _mm256_load_pd(p.oEnter));
  const __m256d b = _mm256_sub_pd(exitPlane, _mm256_load_pd(p.oExit));
  const __m256d enter = _mm256_min_pd(_mm256_mul_pd(a, invLo), _mm256_mul_pd(a, invHi));
  const __m256d exit = _mm256_mul_pd(
      _mm256_max_pd(_mm256_mul_pd(b, invLo), _mm256_mul_pd(b, invHi)), bcast(1.0 + 0x1p-40));
  const __m256d use = _mm256_load_pd(reinterpret_cast<const double*>(p.useAxis));
  const __m256d infinity = bcast(std::numeric_limits<double>::infinity());
  const __m256d enterUsed =
      _mm256_blendv_pd(_mm256_xor_pd(infinity, bcast(-0.0)), enter,
                       _mm256_and_pd(use, _mm256_cmp_pd(enter, enter, _CMP_ORD_Q)));
  const __m256d exitUsed =
      _mm256_blendv_pd(infinity, exit, _mm256_and_pd(use, _mm256_cmp_pd(exit, exit, _CMP_ORD_Q)));
  // Largest entry, smallest exit over the lanes.
  __m256d tNear = _mm256_max_pd(enterUsed, _mm256_permute2f128_pd(enterUsed, enterUsed, 1));
  tNear = _mm256_max_pd(tNear, _mm256_permute_pd(tNear, 5));
  __m256d tFar = _mm256_min_pd(exitUsed, _mm256_permute2f128_pd(exitUsed, exitUsed, 1));
  tFar = _mm256_min_pd(tFar, _mm256_permute_pd(tFar, 5));
  const double entry = std::max(0.0, _mm256_cvtsd_f64(tNear));
  const double leave = std::min(tLimit, _mm256_cvtsd_f64(tFar));
  return entry <= leave;
}

CLIPRAY_AVX2 double maxBest(const Packet& p) {
  __m256d m = _mm256_load_pd(p.bestT);
  for (int base = 4; base < p.lanes; base += 4)
    m = _mm256_max_pd(m, _mm256_load_pd(p.bestT + base));
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, m);
  return std::max(std::max(lanes[0], lanes[1]), std::max(lanes[2], lanes[3]));
}

CLIPRAY_AVX2 void tracePacket(const SceneIntersector& scene, const std::vector<BvhNode>& nodes,
                              const std::vector<Triangle>& triangles, Packet& p, const Ray* rays) {
  const int groups = p.lanes / 4;
  const glm::dvec3 reference = scene.reference();
  double tLimit = maxBest(p) * (1.0 + 0x1p-30);
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = nodes[stack[--top]];
    if (!slabPacket(p, node, tLimit)) continue;
    if (node.count == 0) {
      const std::uint32_t first = static_cast<std::uint32_t>(&node - nodes.data()) + 1;
      const std::uint32_t second = node.first;
      // The second child is far from its parent in memory: start loading it now.
      __builtin_prefetch(&nodes[second]);
      // Near child first (pushed last): the first child holds the smaller centroids.
      if (p.sign[node.axis] < 0) {
        stack[top++] = first;
        stack[top++] = second;
      } else {
        stack[top++] = second;
        stack[top++] = first;
      }
      continue;
    }
    // The leaf's triangles load while its box is tested against the groups.
    {
      const auto* begin = reinterpret_cast<const char*>(&triangles[node.first]);
      const auto bytes = static_cast<std::ptrdiff_t>(node.count * sizeof(Triangle));
      for (std::ptrdiff_t at = 0; at < bytes; at += 64) __builtin_prefetch(begin + at);
    }
    // The groups that may hit the box, without a branch per group (a group's triangle tests
    // change only its own lanes, so testing every box first gives the same masks).
    const WideBox box = wideBox(node);
    std::uint32_t hitGroups = 0;
    for (int g = 0; g < groups; ++g) {
      hitGroups |= static_cast<std::uint32_t>(slabGroup(p, g, box) != 0) << g;
    }
    if (hitGroups == 0) continue;
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const Triangle& tri = triangles[i];
      const WideTriangle wt = wideTriangle(p, tri);
      for (std::uint32_t left = hitGroups; left != 0; left &= left - 1) {
        testGroup(p, std::countr_zero(left), wt, tri, reference, rays);
      }
    }
    tLimit = maxBest(p) * (1.0 + 0x1p-30);
  }
}

// Rays of a tile before they are sorted into packets (structure of arrays).
struct alignas(32) Staged {
  double o[3][kMax];
  double d[3][kMax];
  double tMax[kMax];
  std::uint32_t offset[kMax];
  std::uint8_t laneX[kMax], laneY[kMax];
};

// WatertightRay's shears of lanes base .. base + 3 (p.inv holds their directions): shearX =
// -d[kx] / d[kz] (negation is exact), shearY likewise; returns d[kz].
CLIPRAY_AVX2 inline __m256d storeShearXY(Packet& p, int base) {
  const __m256d signBit = bcast(-0.0);
  const __m256d dkz = _mm256_load_pd(p.inv[p.kz] + base);
  _mm256_store_pd(p.shearX + base,
                  _mm256_div_pd(_mm256_xor_pd(_mm256_load_pd(p.inv[p.kx] + base), signBit), dkz));
  _mm256_store_pd(p.shearY + base,
                  _mm256_div_pd(_mm256_xor_pd(_mm256_load_pd(p.inv[p.ky] + base), signBit), dkz));
  return dkz;
}

// Divisions of WatertightRay and the inverse directions, four lanes at a time (IEEE division is
// correctly rounded, so the same values as the scalar code), then the packet's bounds. On entry
// p.inv holds the directions; padding lanes copy lane 0, so the bounds are those of the rays.
CLIPRAY_AVX2 void preparePacket(Packet& p) {
  const __m256d one = bcast(1.0);
  __m256d oMin[3], oMax[3], invMin[3], invMax[3];
  for (int base = 0; base < p.lanes; base += 4) {
    storeShearXY(p, base);  // shearZ = 1 / d[kz] = inv[kz], stored below
    for (int k = 0; k < 3; ++k) {
      const __m256d inv = _mm256_div_pd(one, _mm256_load_pd(p.inv[k] + base));
      _mm256_store_pd(p.inv[k] + base, inv);
      const __m256d o = _mm256_load_pd(p.o[k] + base);
      if (base == 0) {
        oMin[k] = oMax[k] = o;
        invMin[k] = invMax[k] = inv;
      } else {
        oMin[k] = _mm256_min_pd(oMin[k], o);
        oMax[k] = _mm256_max_pd(oMax[k], o);
        invMin[k] = _mm256_min_pd(invMin[k], inv);
        invMax[k] = _mm256_max_pd(invMax[k], inv);
      }
    }
    _mm256_store_pd(p.shearZ + base, _mm256_load_pd(p.inv[p.kz] + base));
  }
  alignas(32) double lo[4], hi[4], ilo[4], ihi[4];
  for (int k = 0; k < 3; ++k) {
    _mm256_store_pd(lo, oMin[k]);
    _mm256_store_pd(hi, oMax[k]);
    _mm256_store_pd(ilo, invMin[k]);
    _mm256_store_pd(ihi, invMax[k]);
    p.oMin[k] = std::min(std::min(lo[0], lo[1]), std::min(lo[2], lo[3]));
    p.oMax[k] = std::max(std::max(hi[0], hi[1]), std::max(hi[2], hi[3]));
    p.invMin[k] = std::min(std::min(ilo[0], ilo[1]), std::min(ilo[2], ilo[3]));
    p.invMax[k] = std::max(std::max(ihi[0], ihi[1]), std::max(ihi[2], ihi[3]));
    p.sign[k] = p.invMin[k] > 0.0 ? 1 : (p.invMax[k] < 0.0 ? -1 : 0);
    const bool positive = p.sign[k] >= 0;
    const bool finite = std::isfinite(p.invMin[k]) && std::isfinite(p.invMax[k]);
    p.oEnter[k] = positive ? p.oMax[k] : p.oMin[k];
    p.oExit[k] = positive ? p.oMin[k] : p.oMax[k];
    p.invLo[k] = p.invMin[k];
    p.invHi[k] = p.invMax[k];
    p.useAxis[k] = p.sign[k] != 0 && finite ? -1 : 0;
    p.planeIndex[k] = positive ? k : 3 + k;  // BvhNode: lower[3], then upper[3]
    p.planeIndex[4 + k] = positive ? 3 + k : k;
  }
  p.oEnter[3] = p.oExit[3] = p.invLo[3] = p.invHi[3] = 0.0;
  p.useAxis[3] = 0;
  p.planeIndex[3] = p.planeIndex[7] = 0;
}

// The part of preparePacket the bins need: the shear divisions only (the bins test no boxes, so
// neither inverse directions nor packet bounds). p.inv keeps the directions.
CLIPRAY_AVX2 void prepareShear(Packet& p) {
  const __m256d one = bcast(1.0);
  for (int base = 0; base < p.lanes; base += 4) {
    _mm256_store_pd(p.shearZ + base, _mm256_div_pd(one, storeShearXY(p, base)));
  }
}

// Whether a lane of the first `used` is one the BVH's slab tests cannot take (traceTile leaves
// those out of packets unless forBins): a zero direction component (p.inv holds directions) or an
// origin far outside the scene.
bool slabTestsUnfit(const Packet& p, int used, double boxPad) {
  for (int l = 0; l < used; ++l) {
    if (p.inv[0][l] == 0.0 || p.inv[1][l] == 0.0 || p.inv[2][l] == 0.0) return true;
    const double maxO =
        std::max(std::abs(p.o[0][l]), std::max(std::abs(p.o[1][l]), std::abs(p.o[2][l])));
    if (maxO * 0x1p-30 > boxPad) return true;
  }
  return false;
}

// Writes the first `used` lanes' hits (Hit{} where none: t = +inf, id 0). Four lanes whose rays are
// neighbours in memory (a row of a tile in scan order) and whose ids fit in 31 bits as two 32-byte
// stores of two hits each, any others one at a time.
CLIPRAY_AVX2 void writeHits(const Packet& p, int used, Hit* hits) {
  static_assert(sizeof(Hit) == 16 && offsetof(Hit, t) == 0 && offsetof(Hit, primitiveId) == 8);
  const __m256d noId = bcast(kNoId);
  const __m256d infinity = bcast(std::numeric_limits<double>::infinity());
  for (int l = 0; l < used; l += 4) {
    const std::uint32_t first = p.rayIndex[l];
    bool together = l + 4 <= used && p.rayIndex[l + 1] == first + 1 &&
                    p.rayIndex[l + 2] == first + 2 && p.rayIndex[l + 3] == first + 3;
    const __m256d id = _mm256_load_pd(p.bestId + l);
    const __m256d miss = _mm256_cmp_pd(id, noId, _CMP_EQ_OQ);
    const __m256d hitId = _mm256_andnot_pd(miss, id);  // 0 where none
    together =
        together && _mm256_movemask_pd(_mm256_cmp_pd(hitId, bcast(0x1p31), _CMP_LT_OQ)) == 0xF;
    if (together) {
      const __m256d t = _mm256_blendv_pd(_mm256_load_pd(p.bestT + l), infinity, miss);
      // The ids as 64-bit integers: the upper half fills the Hit's padding with zeros.
      const __m256d idBits = _mm256_castsi256_pd(_mm256_cvtepu32_epi64(_mm256_cvttpd_epi32(hitId)));
      const __m256d low = _mm256_unpacklo_pd(t, idBits);   // t0 id0 t2 id2
      const __m256d high = _mm256_unpackhi_pd(t, idBits);  // t1 id1 t3 id3
      double* out = reinterpret_cast<double*>(hits + first);
      _mm256_storeu_pd(out, _mm256_permute2f128_pd(low, high, 0x20));
      _mm256_storeu_pd(out + 4, _mm256_permute2f128_pd(low, high, 0x31));
      continue;
    }
    for (int k = l; k < std::min(used, l + 4); ++k) {
      Hit& hit = hits[p.rayIndex[k]];
      if (p.bestId[k] == kNoId) {
        hit = Hit{};
      } else {
        hit.t = p.bestT[k];
        hit.primitiveId = static_cast<std::uint32_t>(p.bestId[k]);
      }
    }
  }
}

// Traces the packet's first `used` lanes (rays of permutation class cls: p.o, directions in
// p.inv, bestT = tMax, bestId = kNoId, rayIndex, laneX/Y) with walk(p, used) -- which calls
// preparePacket and tests the triangles -- and writes their hits.
template <class Walk>
void runPacket(Packet& p, int cls, int used, Hit* hits, Walk&& walk) {
  p.kz = cls / 2;
  p.kx = (p.kz + 1) % 3;
  p.ky = (p.kx + 1) % 3;
  if (cls % 2 != 0) std::swap(p.kx, p.ky);
  int lanes = used;
  while (lanes % 4 != 0) {  // padding lanes: a copy of lane 0 that never hits
    for (int k = 0; k < 3; ++k) {
      p.o[k][lanes] = p.o[k][0];
      p.inv[k][lanes] = p.inv[k][0];
    }
    p.bestT[lanes] = -1.0;
    p.bestId[lanes] = kNoId;
    p.rayIndex[lanes] = p.rayIndex[0];
    p.laneX[lanes] = p.laneX[0];
    p.laneY[lanes] = p.laneY[0];
    ++lanes;
  }
  p.lanes = lanes;
  walk(p, used);
  writeHits(p, used, hits);
}

// Sorts a tile's rays into packets by permutation class and runs walk(p, used, scanOrder) on
// each (scanOrder: the packet is the whole tile in scan order, lane = y * width + x).
// Six permutation classes (kz, and whether kx/ky are swapped); rays outside every class
// (non-finite, zero direction component, origin far outside the scene) go one at a time.
// Rays in scan order, straight into the packet: most tiles are one class, and then this is the
// packet; otherwise the classes are gathered from a copy.
// The common case of traceTile without a branch per ray: every ray of a tile whose width is a
// multiple of 4 goes into one packet (finite, tMax > 0, no zero direction component, origin near
// the scene, one permutation class). Copies the tile in scan order and checks it four lanes at a
// time with the same arithmetic as traceTile's loop (the world sum in the same order, the same
// class rule), so it accepts exactly the tiles that loop would put into one packet. Returns the
// class, or -1 (then p holds garbage and traceTile's loop runs).
// With forBins, rays with a zero direction component or an origin far from the scene are taken
// too (see traceTile).
CLIPRAY_AVX2 int loadUniformTile(Packet& p, const Ray* rays, std::size_t rowStride, int width,
                                 int height, const glm::dvec3& reference, double boxPad,
                                 bool forBins) {
  // Four rays at a time: each ray's seven doubles as two overlapping loads (origin + d.x, and
  // direction + tMax), transposed into the packet's columns. The origins stay in world
  // coordinates until the checks below.
  static_assert(sizeof(Ray) == 7 * sizeof(double));
  int count = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; x += 4, count += 4) {
      const auto offset = static_cast<std::uint32_t>(static_cast<std::size_t>(y) * rowStride + x);
      const simd::FourRays four = simd::loadFourRays(&rays[offset]);
      _mm256_store_pd(p.o[0] + count, four.originX);
      _mm256_store_pd(p.o[1] + count, four.originY);
      _mm256_store_pd(p.o[2] + count, four.originZ);
      _mm256_store_pd(p.inv[0] + count, four.directionX);
      _mm256_store_pd(p.inv[1] + count, four.directionY);
      _mm256_store_pd(p.inv[2] + count, four.directionZ);
      _mm256_store_pd(p.bestT + count, four.tMax);
      _mm256_store_pd(p.bestId + count, bcast(kNoId));
      for (int l = 0; l < 4; ++l) {
        p.rayIndex[count + l] = offset + static_cast<std::uint32_t>(l);
        p.laneX[count + l] = static_cast<std::uint8_t>(x + l);
        p.laneY[count + l] = static_cast<std::uint8_t>(y);
      }
    }
  }
  const glm::dvec3 d0(p.inv[0][0], p.inv[1][0], p.inv[2][0]);
  const glm::dvec3 a0 = glm::abs(d0);
  const int kz0 = a0.x > a0.y ? (a0.x > a0.z ? 0 : 2) : (a0.y > a0.z ? 1 : 2);
  const int cls = kz0 * 2 + (d0[kz0] < 0.0 ? 1 : 0);
  const __m256d allOnes = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  const __m256d want0 = kz0 == 0 ? allOnes : _mm256_setzero_pd();
  const __m256d want1 = kz0 == 1 ? allOnes : _mm256_setzero_pd();
  const __m256d want2 = kz0 == 2 ? allOnes : _mm256_setzero_pd();
  const __m256d wantNegative = d0[kz0] < 0.0 ? allOnes : _mm256_setzero_pd();
  const __m256d zero = _mm256_setzero_pd();
  const __m256d signBit = bcast(-0.0);
  const __m256d pad = bcast(boxPad);
  const __m256d ref[3] = {bcast(reference.x), bcast(reference.y), bcast(reference.z)};
  __m256d good = allOnes;
  for (int base = 0; base < count; base += 4) {
    __m256d o[3], d[3];
    for (int k = 0; k < 3; ++k) {
      o[k] = _mm256_load_pd(p.o[k] + base);
      d[k] = _mm256_load_pd(p.inv[k] + base);
    }
    // The world sum, left to right as traceTile adds it; finite <=> sum - sum == 0.
    const __m256d sum = _mm256_add_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_add_pd(o[0], o[1]), o[2]), d[0]), d[1]),
        d[2]);
    good = _mm256_and_pd(good, _mm256_cmp_pd(_mm256_sub_pd(sum, sum), zero, _CMP_EQ_OQ));
    good = _mm256_and_pd(good, _mm256_cmp_pd(_mm256_load_pd(p.bestT + base), zero, _CMP_GT_OQ));
    __m256d absO[3], absD[3];
    for (int k = 0; k < 3; ++k) {
      o[k] = _mm256_sub_pd(o[k], ref[k]);
      _mm256_store_pd(p.o[k] + base, o[k]);
      absO[k] = _mm256_andnot_pd(signBit, o[k]);
      absD[k] = _mm256_andnot_pd(signBit, d[k]);
      if (!forBins) good = _mm256_and_pd(good, _mm256_cmp_pd(d[k], zero, _CMP_NEQ_OQ));
    }
    const __m256d maxO = _mm256_max_pd(absO[0], _mm256_max_pd(absO[1], absO[2]));
    if (!forBins) {
      good =
          _mm256_and_pd(good, _mm256_cmp_pd(_mm256_mul_pd(maxO, bcast(0x1p-30)), pad, _CMP_LE_OQ));
    }
    const __m256d xy = _mm256_cmp_pd(absD[0], absD[1], _CMP_GT_OQ);
    const __m256d xz = _mm256_cmp_pd(absD[0], absD[2], _CMP_GT_OQ);
    const __m256d yz = _mm256_cmp_pd(absD[1], absD[2], _CMP_GT_OQ);
    const __m256d is0 = _mm256_and_pd(xy, xz);
    const __m256d is1 = _mm256_andnot_pd(xy, yz);
    const __m256d is2 = _mm256_andnot_pd(_mm256_or_pd(is0, is1), allOnes);
    const __m256d sameAxis =
        _mm256_or_pd(_mm256_or_pd(_mm256_and_pd(is0, want0), _mm256_and_pd(is1, want1)),
                     _mm256_and_pd(is2, want2));
    const __m256d dz = _mm256_blendv_pd(_mm256_blendv_pd(d[2], d[1], is1), d[0], is0);
    const __m256d negative = _mm256_cmp_pd(dz, zero, _CMP_LT_OQ);
    const __m256d sameSign = _mm256_andnot_pd(_mm256_xor_pd(negative, wantNegative), allOnes);
    good = _mm256_and_pd(good, _mm256_and_pd(sameAxis, sameSign));
  }
  return _mm256_movemask_pd(good) == 0xF ? cls : -1;
}

// oneRay(ray) answers a ray that no packet takes (SceneIntersector::closestTriangleHit); boxPad is
// the intersector's box padding. forBins: rays with a zero direction component or an origin far
// outside the scene go into the packets too (the watertight test takes them: d[kz] is the largest
// component; only the BVH's slab tests cannot, so a walk that may use the BVH must check
// slabTestsUnfit first).
template <class OneRay, class Walk>
void traceTile(const SceneIntersector& scene, double boxPad, bool forBins, OneRay&& oneRay,
               const Ray* rays, Hit* hits, std::size_t rowStride, int width, int height,
               Walk&& walk) {
  Packet p;
  const glm::dvec3 reference = scene.reference();
  if (width % 4 == 0) {
    const int uniform =
        loadUniformTile(p, rays, rowStride, width, height, reference, boxPad, forBins);
    if (uniform >= 0) {
      runPacket(p, uniform, width * height, hits,
                [&](Packet& packet, int used) { walk(packet, used, true); });
      return;
    }
  }
  std::uint8_t classOf[kMax];
  int count = 0;
  int classCount[6] = {};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const auto offset = static_cast<std::uint32_t>(static_cast<std::size_t>(y) * rowStride + x);
      const Ray& ray = rays[offset];
      const double sum = ray.origin.x + ray.origin.y + ray.origin.z + ray.direction.x +
                         ray.direction.y + ray.direction.z;
      if (!std::isfinite(sum) || !(ray.tMax > 0.0)) {
        hits[offset] = Hit{};  // what closestHit answers for these
        continue;
      }
      const glm::dvec3 o = ray.origin - reference;
      const glm::dvec3 d = ray.direction;
      if (!forBins && (d.x == 0.0 || d.y == 0.0 || d.z == 0.0 || maxAbs(o) * 0x1p-30 > boxPad)) {
        hits[offset] = oneRay(ray);  // primitives: by the caller
        continue;
      }
      // WatertightRay's permutation: kz, then kx/ky swapped when d[kz] < 0.
      const glm::dvec3 absD = glm::abs(d);
      const int kz = absD.x > absD.y ? (absD.x > absD.z ? 0 : 2) : (absD.y > absD.z ? 1 : 2);
      const int cls = kz * 2 + (d[kz] < 0.0 ? 1 : 0);
      for (int k = 0; k < 3; ++k) {
        p.o[k][count] = o[k];
        p.inv[k][count] = d[k];  // the direction until preparePacket divides
      }
      p.bestT[count] = ray.tMax;
      p.bestId[count] = kNoId;
      p.rayIndex[count] = offset;
      p.laneX[count] = static_cast<std::uint8_t>(x);
      p.laneY[count] = static_cast<std::uint8_t>(y);
      classOf[count] = static_cast<std::uint8_t>(cls);
      ++classCount[cls];
      ++count;
    }
  }
  if (count == 0) return;
  const int first = classOf[0];
  if (classCount[first] == count) {
    const bool scanOrder = count == width * height;
    runPacket(p, first, count, hits,
              [&](Packet& packet, int used) { walk(packet, used, scanOrder); });
    return;
  }
  Staged s;
  for (int i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) {
      s.o[k][i] = p.o[k][i];
      s.d[k][i] = p.inv[k][i];
    }
    s.tMax[i] = p.bestT[i];
    s.offset[i] = p.rayIndex[i];
    s.laneX[i] = p.laneX[i];
    s.laneY[i] = p.laneY[i];
  }
  for (int cls = 0; cls < 6; ++cls) {
    if (classCount[cls] == 0) continue;
    int lanes = 0;
    for (int i = 0; i < count; ++i) {
      if (classOf[i] != cls) continue;
      for (int k = 0; k < 3; ++k) {
        p.o[k][lanes] = s.o[k][i];
        p.inv[k][lanes] = s.d[k][i];
      }
      p.bestT[lanes] = s.tMax[i];
      p.bestId[lanes] = kNoId;
      p.rayIndex[lanes] = s.offset[i];
      p.laneX[lanes] = s.laneX[i];
      p.laneY[lanes] = s.laneY[i];
      ++lanes;
    }
    runPacket(p, cls, lanes, hits, [&](Packet& packet, int used) { walk(packet, used, false); });
  }
}

}  // namespace

bool PacketKernels::available() {
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return avx2 && simdKernelsChosen();
}

void PacketKernels::trace(const SceneIntersector& scene, const Ray* rays, Hit* hits,
                          std::size_t rowStride, int width, int height) noexcept {
  const auto oneRay = [&](const Ray& ray) { return scene.closestTriangleHit(ray); };
  traceTile(scene, scene.boxPad_, false, oneRay, rays, hits, rowStride, width, height,
            [&](Packet& p, int, bool) {
              preparePacket(p);
              scene.ensureBvh();
              tracePacket(scene, scene.bvh_->nodes, scene.bvh_->triangles, p, rays);
            });
}

bool PacketKernels::traceBinned(const SceneIntersector& scene, const FrameBins& bins, int tileX,
                                int tileY, const Ray* rays, Hit* hits, std::size_t rowStride,
                                int width, int height) noexcept {
  bool anyBinned = false, anyWalked = false;
  bool oneAtATime = false;
  const auto oneRay = [&](const Ray& ray) {
    oneAtATime = true;
    return scene.closestTriangleHit(ray);
  };
  // Rays with a zero direction component (an axis-aligned orthographic camera's) or an origin far
  // outside the scene are packed: the bins need no slab tests. A packet with such rays that strays
  // from its pixels is answered one ray at a time.
  traceTile(
      scene, scene.boxPad_, true, oneRay, rays, hits, rowStride, width, height,
      [&](Packet& p, int used, bool scanOrder) {
        if (raysOnTheirPixels(p, used, scanOrder && width == 8 && used == 64, bins, tileX, tileY)) {
          prepareShear(p);
          anyBinned = true;
          traceBins(scene, scene.triangles_, bins, tileX, tileY, p, scanOrder && width == 8, rays);
        } else if (scene.triangles_.empty()) {
          anyWalked = true;  // no triangle to hit: the lanes keep "no hit"
        } else if (slabTestsUnfit(p, used, scene.boxPad_)) {
          oneAtATime = true;
          for (int l = 0; l < used; ++l) {
            const Hit hit = scene.closestTriangleHit(rays[p.rayIndex[l]]);
            p.bestT[l] = hit.t;
            p.bestId[l] = hit.hit() ? static_cast<double>(hit.primitiveId) : kNoId;
          }
        } else {
          preparePacket(p);
          anyWalked = true;
          scene.ensureBvh();
          tracePacket(scene, scene.bvh_->nodes, scene.bvh_->triangles, p, rays);
        }
      });
  return anyBinned && !anyWalked && !oneAtATime;
}

#else

bool PacketKernels::available() {
  return false;
}
bool PacketKernels::traceBinned(const SceneIntersector& scene, const FrameBins&, int, int,
                                const Ray* rays, Hit* hits, std::size_t rowStride, int width,
                                int height) noexcept {
  trace(scene, rays, hits, rowStride, width, height);
  return false;
}
void PacketKernels::trace(const SceneIntersector& scene, const Ray* rays, Hit* hits,
                          std::size_t rowStride, int width, int height) noexcept {
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * rowStride + x;
      hits[i] = scene.closestTriangleHit(rays[i]);
    }
  }
}

#endif

}  // namespace clipray::detail

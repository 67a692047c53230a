// Packet traversal for coherent rays (a tile of primary rays), bit-identical to closestHit's
// triangle part (SceneIntersector::closestHitsTile then adds the analytic primitives).
//
// Rays are grouped by their watertight axis permutation (kx, ky, kz); each group is one packet,
// stored as structure-of-arrays and processed four rays per AVX2 instruction. The BVH is walked
// once per packet:
// - inner nodes: one interval-arithmetic slab test for the whole packet (origins and inverse
//   directions bounded per axis), conservative by construction, plus the packet's largest
//   current best t;
// - leaves: an exact-or-wider slab test per group of four rays, then the watertight triangle
//   test of Watertight.hpp for each group that may hit, operation for operation as the scalar
//   code does it (separate multiplies and adds; the AVX2 target has no FMA to contract into).
// Hits keep the smallest (t, primitive id), so the visiting order never changes the answer; the
// rare lanes whose edge function is exactly zero take the scalar path for that triangle.

#include "clipray/intersect/PacketKernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>

#include "clipray/intersect/Watertight.hpp"

#if defined(__x86_64__) || defined(__i386__)
#define CLIPRAY_HAVE_AVX2_KERNELS 1
#include <immintrin.h>
#else
#define CLIPRAY_HAVE_AVX2_KERNELS 0
#endif

namespace clipray::detail {

#if CLIPRAY_HAVE_AVX2_KERNELS

namespace {

#define CLIPRAY_AVX2 __attribute__((target("avx2")))

constexpr std::size_t kMax = SceneIntersector::kMaxPacket;
constexpr double kNoId = 0x1p40;  // larger than any primitive id: "no hit yet"

double maxAbs(const glm::dvec3& p) {
  return std::max(std::abs(p.x), std::max(std::abs(p.y), std::abs(p.z)));
}

struct alignas(32) Packet {
  double o[3][kMax];    // origin relative to the reference
  double inv[3][kMax];  // 1 / direction
  double shearX[kMax], shearY[kMax], shearZ[kMax];
  double bestT[kMax];
  double bestId[kMax];
  std::uint32_t rayIndex[kMax];
  int lanes = 0;  // multiple of 4; padding lanes have bestT = -1 and never hit
  int kx = 0, ky = 0, kz = 0;
  // Packet bounds for the interval slab test; sign: +1 or -1 when all inverse directions on
  // the axis share it, 0 when they do not (the axis is then not used to cull).
  double oMin[3], oMax[3], invMin[3], invMax[3];
  int sign[3];
};

using Triangle = BvhTriangle;

// Keeps (t, id) when it is smaller than the lane's best: the scalar rule of closestHit.
void scalarLane(Packet& p, int lane, const WatertightRay& ray, const Triangle& tri) {
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

// The watertight test of one triangle against four lanes of the packet.
CLIPRAY_AVX2 inline void testGroup(Packet& p, int g, const Triangle& tri,
                                   const glm::dvec3& reference, const Ray* rays) {
  const int base = g * 4;
  const __m256d okx = _mm256_load_pd(p.o[p.kx] + base);
  const __m256d oky = _mm256_load_pd(p.o[p.ky] + base);
  const __m256d okz = _mm256_load_pd(p.o[p.kz] + base);
  const __m256d sx = _mm256_load_pd(p.shearX + base);
  const __m256d sy = _mm256_load_pd(p.shearY + base);
  const __m256d Akz = _mm256_sub_pd(bcast(tri.a[p.kz]), okz);
  const __m256d Bkz = _mm256_sub_pd(bcast(tri.b[p.kz]), okz);
  const __m256d Ckz = _mm256_sub_pd(bcast(tri.c[p.kz]), okz);
  const __m256d ax = _mm256_add_pd(_mm256_sub_pd(bcast(tri.a[p.kx]), okx), _mm256_mul_pd(sx, Akz));
  const __m256d ay = _mm256_add_pd(_mm256_sub_pd(bcast(tri.a[p.ky]), oky), _mm256_mul_pd(sy, Akz));
  const __m256d bx = _mm256_add_pd(_mm256_sub_pd(bcast(tri.b[p.kx]), okx), _mm256_mul_pd(sx, Bkz));
  const __m256d by = _mm256_add_pd(_mm256_sub_pd(bcast(tri.b[p.ky]), oky), _mm256_mul_pd(sy, Bkz));
  const __m256d cx = _mm256_add_pd(_mm256_sub_pd(bcast(tri.c[p.kx]), okx), _mm256_mul_pd(sx, Ckz));
  const __m256d cy = _mm256_add_pd(_mm256_sub_pd(bcast(tri.c[p.ky]), oky), _mm256_mul_pd(sy, Ckz));
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
  const int candidate = _mm256_movemask_pd(_mm256_andnot_pd(onEdge, inside));
  if (candidate != 0) {
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
    const __m256d id = bcast(static_cast<double>(tri.primitiveId));
    const __m256d better = _mm256_or_pd(
        _mm256_cmp_pd(t, bestT, _CMP_LT_OQ),
        _mm256_and_pd(_mm256_cmp_pd(t, bestT, _CMP_EQ_OQ), _mm256_cmp_pd(id, bestId, _CMP_LT_OQ)));
    const __m256d valid = _mm256_and_pd(
        _mm256_and_pd(_mm256_cmp_pd(det, zero, _CMP_NEQ_OQ), _mm256_cmp_pd(t, zero, _CMP_GT_OQ)),
        _mm256_andnot_pd(onEdge, inside));
    const __m256d accept = _mm256_and_pd(valid, better);
    if (_mm256_movemask_pd(accept) != 0) {
      _mm256_store_pd(p.bestT + base, _mm256_blendv_pd(bestT, t, accept));
      _mm256_store_pd(p.bestId + base, _mm256_blendv_pd(bestId, id, accept));
    }
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

// Slab test of one box against four lanes: a bit per lane that may hit it before its best t.
CLIPRAY_AVX2 inline int slabGroup(const Packet& p, int g, const BvhNode& node) {
  const int base = g * 4;
  __m256d tNear = _mm256_setzero_pd();
  __m256d tFar = _mm256_mul_pd(_mm256_load_pd(p.bestT + base), bcast(1.0 + 0x1p-30));
  for (int k = 0; k < 3; ++k) {
    const __m256d o = _mm256_load_pd(p.o[k] + base);
    const __m256d inv = _mm256_load_pd(p.inv[k] + base);
    const __m256d t0 = _mm256_mul_pd(_mm256_sub_pd(bcast(node.lower[k]), o), inv);
    const __m256d t1 = _mm256_mul_pd(_mm256_sub_pd(bcast(node.upper[k]), o), inv);
    // Directions have no zero component here (those rays take the scalar path): no NaN.
    tNear = _mm256_max_pd(tNear, _mm256_min_pd(t0, t1));
    tFar = _mm256_min_pd(tFar, _mm256_mul_pd(_mm256_max_pd(t0, t1), bcast(1.0 + 0x1p-40)));
  }
  return _mm256_movemask_pd(_mm256_cmp_pd(tNear, tFar, _CMP_LE_OQ));
}

// Interval slab test of a box against the whole packet (inner nodes).
inline bool slabPacket(const Packet& p, const BvhNode& node, double tLimit) {
  double tNear = 0.0, tFar = tLimit;
  for (int k = 0; k < 3; ++k) {
    if (p.sign[k] == 0) continue;
    const double enterPlane = p.sign[k] > 0 ? node.lower[k] : node.upper[k];
    const double exitPlane = p.sign[k] > 0 ? node.upper[k] : node.lower[k];
    // (plane - o) * inv over o in [oMin, oMax], inv in [invMin, invMax]: the extremes are at
    // the interval corners.
    const double e0 = (enterPlane - p.oMax[k]) * p.invMin[k];
    const double e1 = (enterPlane - p.oMax[k]) * p.invMax[k];
    const double e2 = (enterPlane - p.oMin[k]) * p.invMin[k];
    const double e3 = (enterPlane - p.oMin[k]) * p.invMax[k];
    const double x0 = (exitPlane - p.oMax[k]) * p.invMin[k];
    const double x1 = (exitPlane - p.oMax[k]) * p.invMax[k];
    const double x2 = (exitPlane - p.oMin[k]) * p.invMin[k];
    const double x3 = (exitPlane - p.oMin[k]) * p.invMax[k];
    const double enter = std::min(std::min(e0, e1), std::min(e2, e3));
    const double exit = std::max(std::max(x0, x1), std::max(x2, x3)) * (1.0 + 0x1p-40);
    tNear = std::max(tNear, enter);
    tFar = std::min(tFar, exit);
  }
  return tNear <= tFar;
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
    bool any = false;
    for (int g = 0; g < groups; ++g) {
      if (slabGroup(p, g, node) == 0) continue;
      any = true;
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        testGroup(p, g, triangles[i], reference, rays);
      }
    }
    if (any) tLimit = maxBest(p) * (1.0 + 0x1p-30);
  }
}

}  // namespace

bool PacketKernels::available() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}

void PacketKernels::trace(const SceneIntersector& scene, const Ray* rays, Hit* hits,
                          std::size_t rowStride, int width, int height) noexcept {
  // Six permutation classes (kz, and whether kx/ky are swapped); rays outside every class
  // (non-finite, zero direction component, origin far outside the scene) go one at a time.
  struct Prepared {
    WatertightRay ray;
    std::uint32_t offset;  // of the ray in rays / hits
    int cls;
  };
  alignas(64) unsigned char storage[kMax * sizeof(Prepared)];
  auto* prepared = reinterpret_cast<Prepared*>(storage);
  int count = 0;
  int classCount[6] = {};
  const glm::dvec3 reference = scene.reference();
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
      if (ray.direction.x == 0.0 || ray.direction.y == 0.0 || ray.direction.z == 0.0 ||
          maxAbs(o) * 0x1p-30 > scene.boxPad_) {
        hits[offset] = scene.closestTriangleHit(ray);  // primitives: by the caller
        continue;
      }
      Prepared* slot =
          new (&prepared[count++]) Prepared{WatertightRay(o, ray.direction), offset, 0};
      slot->cls = slot->ray.kz * 2 + (slot->ray.kx == (slot->ray.kz + 1) % 3 ? 0 : 1);
      ++classCount[slot->cls];
    }
  }
  Packet p;
  for (int cls = 0; cls < 6; ++cls) {
    if (classCount[cls] == 0) continue;
    int lanes = 0;
    for (int i = 0; i < count; ++i) {
      const Prepared& r = prepared[i];
      if (r.cls != cls) continue;
      const Ray& ray = rays[r.offset];
      p.kx = r.ray.kx;
      p.ky = r.ray.ky;
      p.kz = r.ray.kz;
      for (int k = 0; k < 3; ++k) {
        p.o[k][lanes] = r.ray.origin[k];
        p.inv[k][lanes] = 1.0 / ray.direction[k];
      }
      p.shearX[lanes] = r.ray.shearX;
      p.shearY[lanes] = r.ray.shearY;
      p.shearZ[lanes] = r.ray.shearZ;
      p.bestT[lanes] = ray.tMax;
      p.bestId[lanes] = kNoId;
      p.rayIndex[lanes] = r.offset;
      ++lanes;
    }
    const int used = lanes;
    for (int k = 0; k < 3; ++k) {
      p.oMin[k] = p.oMax[k] = p.o[k][0];
      p.invMin[k] = p.invMax[k] = p.inv[k][0];
      for (int l = 1; l < used; ++l) {
        p.oMin[k] = std::min(p.oMin[k], p.o[k][l]);
        p.oMax[k] = std::max(p.oMax[k], p.o[k][l]);
        p.invMin[k] = std::min(p.invMin[k], p.inv[k][l]);
        p.invMax[k] = std::max(p.invMax[k], p.inv[k][l]);
      }
      p.sign[k] = p.invMin[k] > 0.0 ? 1 : (p.invMax[k] < 0.0 ? -1 : 0);
    }
    while (lanes % 4 != 0) {  // padding lanes: a copy of lane 0 that never hits
      for (int k = 0; k < 3; ++k) {
        p.o[k][lanes] = p.o[k][0];
        p.inv[k][lanes] = p.inv[k][0];
      }
      p.shearX[lanes] = p.shearX[0];
      p.shearY[lanes] = p.shearY[0];
      p.shearZ[lanes] = p.shearZ[0];
      p.bestT[lanes] = -1.0;
      p.bestId[lanes] = kNoId;
      p.rayIndex[lanes] = p.rayIndex[0];
      ++lanes;
    }
    p.lanes = lanes;
    tracePacket(scene, scene.nodes_, scene.triangles_, p, rays);
    for (int l = 0; l < used; ++l) {
      Hit& hit = hits[p.rayIndex[l]];
      if (p.bestId[l] == kNoId) {
        hit = Hit{};
      } else {
        hit.t = p.bestT[l];
        hit.primitiveId = static_cast<std::uint32_t>(p.bestId[l]);
      }
    }
  }
}

#else

bool PacketKernels::available() {
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

// Four rays at a time through Primitives.cpp's intersections. Every step is the scalar code's
// operation on the same operands in the same order: glm's mat3 * vec3 is (a x + b y) + c z and
// its dot products (x + y) + z; division and square root are correctly rounded; the fma of
// lengthSquaredMinusOne is the fused instruction, correctly rounded as std::fma; std::max(a, b),
// std::min(a, b) and std::swap under a comparison are the comparison and a blend. This file is
// compiled with -ffp-contract=off (harness/CMakeLists.txt): no other multiply and add may fuse.

#include "clipray/intersect/PrimitiveKernels.hpp"

#include <limits>

#include "clipray/intersect/Primitives.hpp"
#include "clipray/rays/FourRays.hpp"
#include "clipray/util/KernelChoice.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#define CLIPRAY_PRIMITIVE_KERNELS 1
#include <immintrin.h>
#else
#define CLIPRAY_PRIMITIVE_KERNELS 0
#endif

namespace clipray::detail {

#if CLIPRAY_PRIMITIVE_KERNELS

namespace {

#define CLIPRAY_AVX2_FMA __attribute__((target("avx2,fma")))

constexpr double kInf = std::numeric_limits<double>::infinity();

CLIPRAY_AVX2_FMA inline __m256d bcast(double v) {
  return _mm256_set1_pd(v);
}
CLIPRAY_AVX2_FMA inline __m256d abs4(__m256d v) {
  return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
}
// where ? a : b
CLIPRAY_AVX2_FMA inline __m256d select(__m256d where, __m256d a, __m256d b) {
  return _mm256_blendv_pd(b, a, where);
}
CLIPRAY_AVX2_FMA inline __m256d dot3(const __m256d a[3], const __m256d b[3]) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a[0], b[0]), _mm256_mul_pd(a[1], b[1])),
                       _mm256_mul_pd(a[2], b[2]));
}

// accept(t, tMax): t when 0 < t <= tMax and t < inf, else +inf (NaN never passes).
CLIPRAY_AVX2_FMA inline __m256d accept(__m256d t, __m256d tMax) {
  const __m256d ok = _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(t, _mm256_setzero_pd(), _CMP_GT_OQ),
                                                 _mm256_cmp_pd(t, tMax, _CMP_LE_OQ)),
                                   _mm256_cmp_pd(t, bcast(kInf), _CMP_LT_OQ));
  return select(ok, t, bcast(kInf));
}

// Knuth's TwoSum.
CLIPRAY_AVX2_FMA inline void twoSum(__m256d a, __m256d b, __m256d& s, __m256d& e) {
  const __m256d sum = _mm256_add_pd(a, b);
  const __m256d bb = _mm256_sub_pd(sum, a);
  e = _mm256_add_pd(_mm256_sub_pd(a, _mm256_sub_pd(sum, bb)), _mm256_sub_pd(b, bb));
  s = sum;
}

// lengthSquaredMinusOne.
CLIPRAY_AVX2_FMA inline __m256d lengthSquaredMinusOne(const __m256d v[3]) {
  __m256d p = _mm256_mul_pd(v[0], v[0]);
  __m256d s = _mm256_fmsub_pd(v[0], v[0], p);
  for (int i = 1; i < 3; ++i) {
    const __m256d h = _mm256_mul_pd(v[i], v[i]);
    const __m256d r = _mm256_fmsub_pd(v[i], v[i], h);
    __m256d q;
    twoSum(p, h, p, q);
    s = _mm256_add_pd(s, _mm256_add_pd(q, r));
  }
  __m256d q;
  twoSum(p, bcast(-1.0), p, q);
  s = _mm256_add_pd(s, q);
  return _mm256_add_pd(p, s);
}

// intersectSphere's root before accept; +inf where it answers +inf before.
CLIPRAY_AVX2_FMA inline __m256d sphereT(const __m256d o[3], const __m256d d[3]) {
  const __m256d a = dot3(d, d);
  const __m256d b = dot3(o, d);
  const __m256d ratio = _mm256_div_pd(b, a);
  __m256d l[3];
  for (int i = 0; i < 3; ++i) l[i] = _mm256_sub_pd(o[i], _mm256_mul_pd(ratio, d[i]));
  const __m256d disc = _mm256_mul_pd(a, _mm256_sub_pd(bcast(1.0), dot3(l, l)));
  const __m256d signOfB = _mm256_and_pd(bcast(-0.0), b);
  const __m256d root = _mm256_or_pd(abs4(_mm256_sqrt_pd(disc)), signOfB);  // copysign
  const __m256d q = _mm256_xor_pd(_mm256_add_pd(b, root), bcast(-0.0));    // -(b + root)
  const __m256d c = lengthSquaredMinusOne(o);
  const __m256d r0 = _mm256_div_pd(c, q), r1 = _mm256_div_pd(q, a);
  const __m256d swap = _mm256_cmp_pd(r0, r1, _CMP_GT_OQ);
  const __m256d t0 = select(swap, r1, r0), t1 = select(swap, r0, r1);
  const __m256d t = select(_mm256_cmp_pd(t0, _mm256_setzero_pd(), _CMP_GT_OQ), t0, t1);
  const __m256d miss = _mm256_or_pd(
      _mm256_or_pd(_mm256_cmp_pd(a, _mm256_setzero_pd(), _CMP_NGT_UQ),      // !(a > 0)
                   _mm256_cmp_pd(disc, _mm256_setzero_pd(), _CMP_NGE_UQ)),  // !(disc >= 0)
      _mm256_cmp_pd(q, _mm256_setzero_pd(), _CMP_EQ_OQ));
  return select(miss, bcast(kInf), t);
}

// planeT: t = -o.z / d.z with x, y of the hit; +inf where d.z == 0.
CLIPRAY_AVX2_FMA inline __m256d planeT(const __m256d o[3], const __m256d d[3], __m256d& x,
                                       __m256d& y) {
  const __m256d t = _mm256_div_pd(_mm256_xor_pd(o[2], bcast(-0.0)), d[2]);
  x = _mm256_add_pd(o[0], _mm256_mul_pd(t, d[0]));
  y = _mm256_add_pd(o[1], _mm256_mul_pd(t, d[1]));
  return select(_mm256_cmp_pd(d[2], _mm256_setzero_pd(), _CMP_EQ_OQ), bcast(kInf), t);
}

// intersectBox, accept included.
CLIPRAY_AVX2_FMA inline __m256d boxT(const __m256d o[3], const __m256d d[3], __m256d tMax) {
  __m256d tNear = bcast(-kInf), tFar = bcast(kInf);
  __m256d miss = _mm256_setzero_pd();
  for (int i = 0; i < 3; ++i) {
    const __m256d flat = _mm256_cmp_pd(d[i], _mm256_setzero_pd(), _CMP_EQ_OQ);
    // A zero component: the slab is the origin's (inside it, boundary included, or a miss).
    miss =
        _mm256_or_pd(miss, _mm256_and_pd(flat, _mm256_cmp_pd(abs4(o[i]), bcast(1.0), _CMP_NLE_UQ)));
    const __m256d r0 = _mm256_div_pd(_mm256_sub_pd(bcast(-1.0), o[i]), d[i]);
    const __m256d r1 = _mm256_div_pd(_mm256_sub_pd(bcast(1.0), o[i]), d[i]);
    const __m256d swap = _mm256_cmp_pd(r0, r1, _CMP_GT_OQ);
    const __m256d t0 = select(swap, r1, r0), t1 = select(swap, r0, r1);
    const __m256d nearer = select(_mm256_cmp_pd(tNear, t0, _CMP_LT_OQ), t0, tNear);  // max
    const __m256d farther = select(_mm256_cmp_pd(t1, tFar, _CMP_LT_OQ), t1, tFar);   // min
    tNear = select(flat, tNear, nearer);
    tFar = select(flat, tFar, farther);
  }
  miss = _mm256_or_pd(miss, _mm256_cmp_pd(tNear, tFar, _CMP_NLE_UQ));  // !(tNear <= tFar)
  const __m256d t =
      accept(select(_mm256_cmp_pd(tNear, _mm256_setzero_pd(), _CMP_GT_OQ), tNear, tFar), tMax);
  return select(miss, bcast(kInf), t);
}

// intersectPrimitive for four rays with bounds tMax (the current best t of each lane).
CLIPRAY_AVX2_FMA __m256d primitiveT(const AnalyticPrimitive& primitive, const simd::FourRays& ray,
                                    __m256d tMax) {
  // toLocal: linear(localFromWorld) * (o - position) and * d.
  const glm::dmat4& m = primitive.localFromWorld;
  const glm::dvec4& position = primitive.worldFromLocal[3];
  const __m256d relative[3] = {_mm256_sub_pd(ray.originX, bcast(position.x)),
                               _mm256_sub_pd(ray.originY, bcast(position.y)),
                               _mm256_sub_pd(ray.originZ, bcast(position.z))};
  const __m256d world[3] = {ray.directionX, ray.directionY, ray.directionZ};
  __m256d o[3], d[3];
  for (int r = 0; r < 3; ++r) {
    o[r] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(bcast(m[0][r]), relative[0]),
                                       _mm256_mul_pd(bcast(m[1][r]), relative[1])),
                         _mm256_mul_pd(bcast(m[2][r]), relative[2]));
    d[r] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(bcast(m[0][r]), world[0]),
                                       _mm256_mul_pd(bcast(m[1][r]), world[1])),
                         _mm256_mul_pd(bcast(m[2][r]), world[2]));
  }
  // intersectCanonical's checks: tMax > 0 (accept implies it) and a finite local ray.
  const __m256d sum = _mm256_add_pd(
      _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_add_pd(o[0], o[1]), o[2]), d[0]), d[1]),
      d[2]);
  const __m256d finite = _mm256_cmp_pd(_mm256_sub_pd(sum, sum), _mm256_setzero_pd(), _CMP_EQ_OQ);
  __m256d t;
  __m256d x, y;
  switch (primitive.kind) {
    case PrimitiveKind::Sphere:
      t = accept(sphereT(o, d), tMax);
      break;
    case PrimitiveKind::Disk: {
      t = accept(planeT(o, d, x, y), tMax);
      const __m256d inside = _mm256_cmp_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)),
                                           bcast(1.0), _CMP_LE_OQ);
      t = select(inside, t, bcast(kInf));
      break;
    }
    case PrimitiveKind::Quad: {
      t = accept(planeT(o, d, x, y), tMax);
      const __m256d inside = _mm256_and_pd(_mm256_cmp_pd(abs4(x), bcast(1.0), _CMP_LE_OQ),
                                           _mm256_cmp_pd(abs4(y), bcast(1.0), _CMP_LE_OQ));
      t = select(inside, t, bcast(kInf));
      break;
    }
    case PrimitiveKind::Box:
      t = boxT(o, d, tMax);
      break;
    case PrimitiveKind::Plane:
    default:
      t = accept(planeT(o, d, x, y), tMax);
      break;
  }
  return select(finite, t, bcast(kInf));
}

}  // namespace

bool primitiveKernelsAvailable() {
  static const bool avx2Fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return avx2Fma && simdKernelsChosen();
}

CLIPRAY_AVX2_FMA void addPrimitivesToFour(const AnalyticPrimitive* const* primitives,
                                          const std::uint32_t* ids, std::size_t count,
                                          const Ray* rays, Hit* hits) noexcept {
  const simd::FourRays ray = simd::loadFourRays(rays);
  // finiteRay: the six coordinates' sum, left to right, is finite.
  const __m256d sum = _mm256_add_pd(
      _mm256_add_pd(
          _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(ray.originX, ray.originY), ray.originZ),
                        ray.directionX),
          ray.directionY),
      ray.directionZ);
  const __m256d finiteRay = _mm256_cmp_pd(_mm256_sub_pd(sum, sum), _mm256_setzero_pd(), _CMP_EQ_OQ);
  // best = hits[l]; without a hit its t is the ray's tMax (the bound), and +inf again after.
  __m256d bestId = _mm256_set_pd(hits[3].primitiveId, hits[2].primitiveId, hits[1].primitiveId,
                                 hits[0].primitiveId);
  const __m256d noHit = _mm256_cmp_pd(bestId, _mm256_setzero_pd(), _CMP_EQ_OQ);
  __m256d bestT =
      select(noHit, ray.tMax, _mm256_set_pd(hits[3].t, hits[2].t, hits[1].t, hits[0].t));
  for (std::size_t k = 0; k < count; ++k) {
    const __m256d t = primitiveT(*primitives[k], ray, bestT);
    const __m256d id = bcast(static_cast<double>(ids[k]));
    // testAnalytic: a hit (t < inf) replaces the best when nearer, when there is none yet, or
    // when its id is smaller.
    const __m256d replace = _mm256_and_pd(
        _mm256_cmp_pd(t, bcast(kInf), _CMP_LT_OQ),
        _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(t, bestT, _CMP_LT_OQ),
                                  _mm256_cmp_pd(bestId, _mm256_setzero_pd(), _CMP_EQ_OQ)),
                     _mm256_cmp_pd(id, bestId, _CMP_LT_OQ)));
    bestT = select(replace, t, bestT);
    bestId = select(replace, id, bestId);
  }
  alignas(32) double t[4], id[4];
  _mm256_store_pd(t, bestT);
  _mm256_store_pd(id, bestId);
  const int finiteLanes = _mm256_movemask_pd(finiteRay);
  for (int l = 0; l < 4; ++l) {
    if ((finiteLanes >> l & 1) == 0) continue;  // closestHit answers Hit{}: left as it was
    hits[l].primitiveId = static_cast<std::uint32_t>(id[l]);
    hits[l].t = hits[l].primitiveId != 0 ? t[l] : kInf;
  }
}

#else

bool primitiveKernelsAvailable() {
  return false;
}

void addPrimitivesToFour(const AnalyticPrimitive* const*, const std::uint32_t*, std::size_t,
                         const Ray*, Hit*) noexcept {}

#endif

}  // namespace clipray::detail

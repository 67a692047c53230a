#pragma once
// Four consecutive rays of a frame (Ray: seven doubles, origin, direction, tMax) as seven AVX2
// columns, and back: the packet kernels, the compare pass and the robust row kernel move rays
// between the frame's layout and four lanes per register with these.
//
// Each ray is read (written) as two overlapping 32-byte pieces, (origin, direction.x) and
// (direction, tMax), and the pieces of four rays are transposed 4x4: no gather, no per-field move.
// Only for callers compiled for AVX2 (target("avx2") functions on x86-64).

#if defined(__x86_64__) && defined(__GNUC__)

#include <immintrin.h>

#include "clipray/Ray.hpp"

namespace clipray::simd {

struct FourRays {
  __m256d originX, originY, originZ, directionX, directionY, directionZ, tMax;
};

static_assert(sizeof(Ray) == 7 * sizeof(double));

__attribute__((target("avx2"))) inline FourRays loadFourRays(const Ray* rays) {
  const double* r = &rays[0].origin.x;
  const __m256d a0 = _mm256_loadu_pd(r), a1 = _mm256_loadu_pd(r + 7), a2 = _mm256_loadu_pd(r + 14),
                a3 = _mm256_loadu_pd(r + 21);
  const __m256d b0 = _mm256_loadu_pd(r + 3), b1 = _mm256_loadu_pd(r + 10),
                b2 = _mm256_loadu_pd(r + 17), b3 = _mm256_loadu_pd(r + 24);
  // unpacklo/hi pair rays 0 and 1 (2 and 3) per 128-bit half; permute2f128 then joins the halves.
  const __m256d a01lo = _mm256_unpacklo_pd(a0, a1), a01hi = _mm256_unpackhi_pd(a0, a1);
  const __m256d a23lo = _mm256_unpacklo_pd(a2, a3), a23hi = _mm256_unpackhi_pd(a2, a3);
  const __m256d b01lo = _mm256_unpacklo_pd(b0, b1), b01hi = _mm256_unpackhi_pd(b0, b1);
  const __m256d b23lo = _mm256_unpacklo_pd(b2, b3), b23hi = _mm256_unpackhi_pd(b2, b3);
  return {_mm256_permute2f128_pd(a01lo, a23lo, 0x20), _mm256_permute2f128_pd(a01hi, a23hi, 0x20),
          _mm256_permute2f128_pd(a01lo, a23lo, 0x31), _mm256_permute2f128_pd(a01hi, a23hi, 0x31),
          _mm256_permute2f128_pd(b01hi, b23hi, 0x20), _mm256_permute2f128_pd(b01lo, b23lo, 0x31),
          _mm256_permute2f128_pd(b01hi, b23hi, 0x31)};
}

__attribute__((target("avx2"))) inline void storeFourRays(const FourRays& f, Ray* rays) {
  // Rows (origin.xyz, direction.x) and (direction.xyz, tMax) of each ray: the inverse transposes.
  const __m256d oxy02 = _mm256_unpacklo_pd(f.originX, f.originY);  // ray 0, ray 2
  const __m256d oxy13 = _mm256_unpackhi_pd(f.originX, f.originY);  // ray 1, ray 3
  const __m256d ozdx02 = _mm256_unpacklo_pd(f.originZ, f.directionX);
  const __m256d ozdx13 = _mm256_unpackhi_pd(f.originZ, f.directionX);
  const __m256d dxdy02 = _mm256_unpacklo_pd(f.directionX, f.directionY);
  const __m256d dxdy13 = _mm256_unpackhi_pd(f.directionX, f.directionY);
  const __m256d dzt02 = _mm256_unpacklo_pd(f.directionZ, f.tMax);
  const __m256d dzt13 = _mm256_unpackhi_pd(f.directionZ, f.tMax);
  double* r = &rays[0].origin.x;
  // The second piece of each ray overwrites the first's direction.x with the same value.
  _mm256_storeu_pd(r, _mm256_permute2f128_pd(oxy02, ozdx02, 0x20));
  _mm256_storeu_pd(r + 3, _mm256_permute2f128_pd(dxdy02, dzt02, 0x20));
  _mm256_storeu_pd(r + 7, _mm256_permute2f128_pd(oxy13, ozdx13, 0x20));
  _mm256_storeu_pd(r + 10, _mm256_permute2f128_pd(dxdy13, dzt13, 0x20));
  _mm256_storeu_pd(r + 14, _mm256_permute2f128_pd(oxy02, ozdx02, 0x31));
  _mm256_storeu_pd(r + 17, _mm256_permute2f128_pd(dxdy02, dzt02, 0x31));
  _mm256_storeu_pd(r + 21, _mm256_permute2f128_pd(oxy13, ozdx13, 0x31));
  _mm256_storeu_pd(r + 24, _mm256_permute2f128_pd(dxdy13, dzt13, 0x31));
}

}  // namespace clipray::simd

#endif

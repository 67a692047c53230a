// The robust method's coefficients (in __float128) and its SIMD rows (RobustRayKernel.hpp).

#include "clipray/rays/RobustRayKernel.hpp"

#include "clipray/rays/QuadReference.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define CLIPRAY_X86 1
#else
#define CLIPRAY_X86 0
#endif

namespace clipray::detail {

RobustCoefficients robustCoefficients(const glm::dmat4& entries, DepthMode mode,
                                      Viewport viewport) {
  const QuadMat4 m = toQuad(entries);
  const QuadMat4 inverse = inverseQuad(m).value_or(m);
  const QuadVec4 rowX = quadRow(m, 0), rowY = quadRow(m, 1), rowZ = quadRow(m, 2),
                 rowW = quadRow(m, 3);
  const QuadVec3 mx = xyz(rowX), my = xyz(rowY), mw = xyz(rowW);
  const QuadVec3 p = cross(my, mw), q = cross(mw, mx), r = cross(mx, my);
  const Float128 zNear = mode.nearNdcZ(), zFar = mode.farNdcZ();
  const QuadVec3 nearNormal = {rowZ.x - zNear * rowW.x, rowZ.y - zNear * rowW.y,
                               rowZ.z - zNear * rowW.z};
  const QuadVec3 farNormal = {rowZ.x - zFar * rowW.x, rowZ.y - zFar * rowW.y,
                              rowZ.z - zFar * rowW.z};
  const Float128 nearSign = mode.reversed ? -1 : 1;
  const bool parallel = mw.x == 0 && mw.y == 0 && mw.z == 0;
  const Float128 orientation = (parallel ? nearSign * dot(nearNormal, r) : dot(mw, r)) < 0 ? -1 : 1;
  // d at the viewport's centre is R (x' = y' = 0); P and Q are added at the edges.
  const double centreLength =
      std::max({std::abs(toDouble(r.x)), std::abs(toDouble(r.y)), std::abs(toDouble(r.z)),
                std::abs(toDouble(p.x)), std::abs(toDouble(p.y)), std::abs(toDouble(p.z)),
                std::abs(toDouble(q.x)), std::abs(toDouble(q.y)), std::abs(toDouble(q.z))});
  int exponent = 0;
  if (centreLength > 0 && std::isfinite(centreLength)) std::frexp(centreLength, &exponent);
  const Float128 sign = orientation * Float128(std::ldexp(1.0, -exponent));
  const QuadVec4 c0 = quadColumn(inverse, 0), c1 = quadColumn(inverse, 1),
                 c2 = quadColumn(inverse, 2), c3 = quadColumn(inverse, 3);

  // x' = i * (2 / W) + (1 / W - 1), likewise y'.
  const Float128 stepX = Float128(2) / viewport.width, stepY = Float128(2) / viewport.height;
  const Float128 firstX = Float128(1) / viewport.width - 1,
                 firstY = Float128(1) / viewport.height - 1;
  const Float128 pv[3] = {p.x, p.y, p.z}, qv[3] = {q.x, q.y, q.z}, rv[3] = {r.x, r.y, r.z};
  const Float128 c0v[4] = {c0.x, c0.y, c0.z, c0.w}, c1v[4] = {c1.x, c1.y, c1.z, c1.w};
  const Float128 c23v[4] = {zNear * c2.x + c3.x, zNear * c2.y + c3.y, zNear * c2.z + c3.z,
                            zNear * c2.w + c3.w};
  RobustCoefficients k;
  for (int c = 0; c < 3; ++c) {
    k.perI[c] = toDouble(sign * pv[c] * stepX);
    k.perJ[c] = toDouble(sign * qv[c] * stepY);
    k.at0[c] = toDouble(sign * (rv[c] + pv[c] * firstX + qv[c] * firstY));
  }
  for (int c = 0; c < 4; ++c) {
    k.perI[3 + c] = toDouble(c0v[c] * stepX);
    k.perJ[3 + c] = toDouble(c1v[c] * stepY);
    k.at0[3 + c] = toDouble(c23v[c] + c0v[c] * firstX + c1v[c] * firstY);
  }
  k.perI[7] = toDouble(sign * dot(farNormal, p) * stepX);
  k.perJ[7] = toDouble(sign * dot(farNormal, q) * stepY);
  k.at0[7] = toDouble(
      sign * (dot(farNormal, r) + dot(farNormal, p) * firstX + dot(farNormal, q) * firstY));
  k.depthSpan = mode.farNdcZ() - mode.nearNdcZ();
  return k;
}

#if CLIPRAY_X86
namespace {

// Two halves of double lanes rounded to float and joined into 8 float lanes (lower half first).
__attribute__((target("avx2,fma"))) inline __m256 toFloat8(__m256d low, __m256d high) {
  return _mm256_set_m128(_mm256_cvtpd_ps(high), _mm256_cvtpd_ps(low));
}

// What the AVX2 and AVX-512 rows share after the direction, RobustKernel<float>::finish's
// operations 8 lanes at a time: origin N.xyz / N.w and t_max = (z_far - z_near) |d| / (N.w F), +inf
// unless it is positive and finite (ordered compares: NaN fails both), kNoRayTMax unless N.w > 0.
__attribute__((target("avx2,fma"))) inline void storeOriginsAndTMax(const RaySpan<float>& out,
                                                                    int i0, __m256 nx, __m256 ny,
                                                                    __m256 nz, __m256 nw,
                                                                    __m256 farDot, __m256 length,
                                                                    __m256 depthSpan) {
  const __m256 infinity = _mm256_set1_ps(std::numeric_limits<float>::infinity());
  const __m256 inverseW = _mm256_div_ps(_mm256_set1_ps(1.f), nw);
  const __m256 t = _mm256_div_ps(_mm256_mul_ps(depthSpan, length), _mm256_mul_ps(nw, farDot));
  const __m256 valid = _mm256_and_ps(_mm256_cmp_ps(t, _mm256_setzero_ps(), _CMP_GT_OQ),
                                     _mm256_cmp_ps(t, infinity, _CMP_LT_OQ));
  _mm256_storeu_ps(out.originX + i0, _mm256_mul_ps(nx, inverseW));
  _mm256_storeu_ps(out.originY + i0, _mm256_mul_ps(ny, inverseW));
  _mm256_storeu_ps(out.originZ + i0, _mm256_mul_ps(nz, inverseW));
  const __m256 inFront = _mm256_cmp_ps(nw, _mm256_setzero_ps(), _CMP_GT_OQ);
  _mm256_storeu_ps(out.tMax + i0, _mm256_blendv_ps(_mm256_set1_ps(static_cast<float>(kNoRayTMax)),
                                                   _mm256_blendv_ps(infinity, t, valid), inFront));
}

// The last width - i0 < 8 pixels of a row, one at a time (the scalar call's own arithmetic).
void robustRowTail(const RobustKernel<float>& kernel, const double base[8], int i0, int width,
                   const RaySpan<float>& out) {
  if (i0 >= width) return;
  float block[8];
  RobustKernel<float>::blockBase(base, kernel.coefficients.perI, i0, block);
  for (int k = 0; i0 + k < width; ++k) out.store(i0 + k, kernel.finish(base, block, i0, k));
}

// AVX2 + FMA row of robust float rays: 8 pixels per iteration (the direction in two halves of 4
// double lanes), the exact operations of RobustKernel<float>::finish (IEEE sqrt, division and
// conversions are correctly rounded in both), so the batch and the scalar call agree bit for
// bit. Built for the CPU feature, chosen at run time.

}  // namespace

__attribute__((target("avx2,fma"))) void robustRowAvx2(const RobustKernel<float>& kernel, int j,
                                                       int width, const RaySpan<float>& out) {
  double base[8];
  kernel.rowBase(j, base);
  const __m256 lane = _mm256_setr_ps(0.f, 1.f, 2.f, 3.f, 4.f, 5.f, 6.f, 7.f);
  __m256 step[8];
  for (int c = 3; c < 8; ++c) step[c] = _mm256_set1_ps(kernel.perI[c]);
  __m256d directionStep[3], directionBase[3];
  for (int c = 0; c < 3; ++c) {
    directionStep[c] = _mm256_set1_pd(kernel.coefficients.perI[c]);
    directionBase[c] = _mm256_set1_pd(base[c]);
  }
  const __m256d four = _mm256_set1_pd(4.0), eight = _mm256_set1_pd(8.0);
  __m256d pixelLow = _mm256_setr_pd(0.0, 1.0, 2.0, 3.0);  // i of lanes 0..3, exact in double
  const __m256 depthSpan = _mm256_set1_ps(kernel.depthSpan);
  const __m256 one = _mm256_set1_ps(1.f);
  const __m256 constant[3] = {_mm256_set1_ps(kernel.constant.x), _mm256_set1_ps(kernel.constant.y),
                              _mm256_set1_ps(kernel.constant.z)};
  int i0 = 0;
  for (; i0 + 8 <= width; i0 += 8, pixelLow = _mm256_add_pd(pixelLow, eight)) {
    const __m256d pixelHigh = _mm256_add_pd(pixelLow, four);
    __m256d dLow[3], dHigh[3];
    for (int c = 0; c < 3; ++c) {
      dLow[c] = _mm256_fmadd_pd(pixelLow, directionStep[c], directionBase[c]);
      dHigh[c] = _mm256_fmadd_pd(pixelHigh, directionStep[c], directionBase[c]);
    }
    const __m256d squaredLow = _mm256_fmadd_pd(
        dLow[0], dLow[0], _mm256_fmadd_pd(dLow[1], dLow[1], _mm256_mul_pd(dLow[2], dLow[2])));
    const __m256d squaredHigh = _mm256_fmadd_pd(
        dHigh[0], dHigh[0], _mm256_fmadd_pd(dHigh[1], dHigh[1], _mm256_mul_pd(dHigh[2], dHigh[2])));
    const __m256 length = _mm256_sqrt_ps(toFloat8(squaredLow, squaredHigh));
    const __m256 inverseLength = _mm256_div_ps(one, length);
    const __m256d inverseLow = _mm256_cvtps_pd(_mm256_castps256_ps128(inverseLength));
    const __m256d inverseHigh = _mm256_cvtps_pd(_mm256_extractf128_ps(inverseLength, 1));

    float block[8];
    for (int c = 3; c < 8; ++c) {
      block[c] = static_cast<float>(std::fma(double(i0), kernel.coefficients.perI[c], base[c]));
    }
    const __m256 nx = _mm256_fmadd_ps(lane, step[3], _mm256_set1_ps(block[3]));
    const __m256 ny = _mm256_fmadd_ps(lane, step[4], _mm256_set1_ps(block[4]));
    const __m256 nz = _mm256_fmadd_ps(lane, step[5], _mm256_set1_ps(block[5]));
    const __m256 nw = _mm256_fmadd_ps(lane, step[6], _mm256_set1_ps(block[6]));
    const __m256 farDot = _mm256_fmadd_ps(lane, step[7], _mm256_set1_ps(block[7]));
    for (int c = 0; c < 3; ++c) {
      float* to = c == 0 ? out.directionX : (c == 1 ? out.directionY : out.directionZ);
      _mm256_storeu_ps(to + i0, kernel.constantDirection
                                    ? constant[c]
                                    : toFloat8(_mm256_mul_pd(dLow[c], inverseLow),
                                               _mm256_mul_pd(dHigh[c], inverseHigh)));
    }
    storeOriginsAndTMax(out, i0, nx, ny, nz, nw, farDot, length, depthSpan);
  }
  robustRowTail(kernel, base, i0, width, out);
}

namespace {

// 8 double lanes rounded to 8 float lanes. The masked form (all lanes) because GCC 12's unmasked
// intrinsic trips -Wmaybe-uninitialized inside its own header.
__attribute__((target("avx512f,avx2,fma"))) inline __m256 toFloat8(__m512d lanes) {
  return _mm512_mask_cvtpd_ps(_mm256_setzero_ps(), 0xFF, lanes);
}

// The same row with the direction's 8 pixels in one register of 8 double lanes (AVX-512F): the
// same operations, so the same bits, in fewer instructions (no halves to split and join).

}  // namespace

__attribute__((target("avx512f,avx2,fma"))) void robustRowAvx512(const RobustKernel<float>& kernel,
                                                                 int j, int width,
                                                                 const RaySpan<float>& out) {
  double base[8];
  kernel.rowBase(j, base);
  const __m256 lane = _mm256_setr_ps(0.f, 1.f, 2.f, 3.f, 4.f, 5.f, 6.f, 7.f);
  __m256 step[8];
  for (int c = 3; c < 8; ++c) step[c] = _mm256_set1_ps(kernel.perI[c]);
  __m512d directionStep[3], directionBase[3];
  for (int c = 0; c < 3; ++c) {
    directionStep[c] = _mm512_set1_pd(kernel.coefficients.perI[c]);
    directionBase[c] = _mm512_set1_pd(base[c]);
  }
  const __m512d blockStep = _mm512_maskz_loadu_pd(0x1F, kernel.coefficients.perI + 3);
  const __m512d blockRowBase = _mm512_maskz_loadu_pd(0x1F, base + 3);
  const __m512d eight = _mm512_set1_pd(8.0);
  __m512d pixel = _mm512_setr_pd(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0);
  const __m256 depthSpan = _mm256_set1_ps(kernel.depthSpan);
  const __m256 one = _mm256_set1_ps(1.f);
  const __m256 constant[3] = {_mm256_set1_ps(kernel.constant.x), _mm256_set1_ps(kernel.constant.y),
                              _mm256_set1_ps(kernel.constant.z)};
  int i0 = 0;
  for (; i0 + 8 <= width; i0 += 8, pixel = _mm512_add_pd(pixel, eight)) {
    const __m512d dx = _mm512_fmadd_pd(pixel, directionStep[0], directionBase[0]);
    const __m512d dy = _mm512_fmadd_pd(pixel, directionStep[1], directionBase[1]);
    const __m512d dz = _mm512_fmadd_pd(pixel, directionStep[2], directionBase[2]);
    const __m512d squared = _mm512_fmadd_pd(dx, dx, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dz, dz)));
    const __m256 length = _mm256_sqrt_ps(toFloat8(squared));
    const __m256 inverseLength = _mm256_div_ps(one, length);
    const __m512d inverse = _mm512_mask_cvtps_pd(_mm512_setzero_pd(), 0xFF, inverseLength);

    // The block bases of components 3..7 (lanes 0..4), as blockBase computes them, in one go.
    alignas(32) float blockLanes[8];
    const __m256 block =
        toFloat8(_mm512_fmadd_pd(_mm512_set1_pd(static_cast<double>(i0)), blockStep, blockRowBase));
    _mm256_store_ps(blockLanes, block);
    const __m256 nx = _mm256_fmadd_ps(lane, step[3], _mm256_broadcast_ss(blockLanes + 0));
    const __m256 ny = _mm256_fmadd_ps(lane, step[4], _mm256_broadcast_ss(blockLanes + 1));
    const __m256 nz = _mm256_fmadd_ps(lane, step[5], _mm256_broadcast_ss(blockLanes + 2));
    const __m256 nw = _mm256_fmadd_ps(lane, step[6], _mm256_broadcast_ss(blockLanes + 3));
    const __m256 farDot = _mm256_fmadd_ps(lane, step[7], _mm256_broadcast_ss(blockLanes + 4));
    _mm256_storeu_ps(out.directionX + i0,
                     kernel.constantDirection ? constant[0] : toFloat8(_mm512_mul_pd(dx, inverse)));
    _mm256_storeu_ps(out.directionY + i0,
                     kernel.constantDirection ? constant[1] : toFloat8(_mm512_mul_pd(dy, inverse)));
    _mm256_storeu_ps(out.directionZ + i0,
                     kernel.constantDirection ? constant[2] : toFloat8(_mm512_mul_pd(dz, inverse)));
    storeOriginsAndTMax(out, i0, nx, ny, nz, nw, farDot, length, depthSpan);
  }
  robustRowTail(kernel, base, i0, width, out);
}
#endif

}  // namespace clipray::detail

#include "clipray/rays/RobustRays.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "clipray/math/Projections.hpp"
#include "clipray/rays/FourRays.hpp"
#include "clipray/rays/QuadReference.hpp"
#include "clipray/util/KernelChoice.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#define CLIPRAY_ROW_KERNELS 1
#include <immintrin.h>
#else
#define CLIPRAY_ROW_KERNELS 0
#endif

namespace clipray {

void cutToClipPlanes(Ray& ray, std::span<const glm::dvec4> clipPlanes) noexcept {
  if (clipPlanes.empty() || ray.tMax < 0.0) return;
  // Along the ray each plane's value is s0 + s1 t: it keeps t >= -s0 / s1 where s1 > 0, t <=
  // -s0 / s1 where s1 < 0, and everything or nothing where s1 = 0 (a plane parallel to it).
  double low = 0.0;
  double high = ray.tMax;
  for (const glm::dvec4& plane : clipPlanes) {
    const double s0 = glm::dot(glm::dvec3(plane), ray.origin) + plane.w;
    const double s1 = glm::dot(glm::dvec3(plane), ray.direction);
    if (s1 > 0.0) {
      low = std::max(low, -s0 / s1);
    } else if (s1 < 0.0) {
      high = std::min(high, -s0 / s1);
    } else if (s0 < 0.0) {
      high = -1.0;
    }
  }
  if (!(low < high)) {
    ray.tMax = 0.0;  // the planes leave nothing of this line of sight
    return;
  }
  if (low > 0.0) ray.origin += low * ray.direction;
  ray.tMax = high - low;  // +inf stays +inf
}

RobustRayGenerator::RobustRayGenerator(const glm::dmat4& drawnClipFromWorld, DepthMode drawnMode,
                                       std::span<const glm::dvec4> clipPlanes,
                                       DepthClampRays depthClamp)
    : clipPlanes_(clipPlanes.begin(), clipPlanes.end()),
      depthClamp_(depthClamp),
      clipFromWorld_(lowerLeftClipFromWorld(drawnClipFromWorld, drawnMode.origin)),
      worldFromClip_(glm::inverse(clipFromWorld_)),
      mode_(drawnMode.lowerLeft()) {
  const glm::dmat4& clipFromWorld = clipFromWorld_;
  const DepthMode mode = mode_;
  const glm::dvec4 rowX = matrixRow(clipFromWorld, 0);
  const glm::dvec4 rowY = matrixRow(clipFromWorld, 1);
  const glm::dvec4 rowZ = matrixRow(clipFromWorld, 2);
  const glm::dvec4 rowW = matrixRow(clipFromWorld, 3);
  const glm::dvec3 mx(rowX), my(rowY), mw(rowW);
  myCrossMw_ = glm::cross(my, mw);
  mwCrossMx_ = glm::cross(mw, mx);
  mxCrossMy_ = glm::cross(mx, my);
  nearPlane_ = rowZ - mode.nearNdcZ() * rowW;
  farPlane_ = rowZ - mode.farNdcZ() * rowW;
  parallel_ = mw == glm::dvec3(0.0);
  if (parallel_) {
    // Inside the clip volume z_n w <= z <= w: the plane z - z_n w is >= 0 for the classic near
    // plane; for reversed-Z the near plane is z - w, which is <= 0 inside.
    facingNormal_ = glm::dvec3(nearPlane_);
    facingSign_ = mode.reversed ? -1.0 : 1.0;
  } else {
    // dot(mw, d) = det(mx, my, mw) at every pixel (d = x' my x mw + y' mw x mx + mx x my): one
    // sign for the whole frame, never near zero, where the near plane's dot with d changes sign
    // at the horizon of an oblique near plane. The direction is robustDirectionSign's: away from
    // the eye (w growing) for every ordinary camera and for Lengyel's, towards it for a matrix
    // whose near plane lies on the eye's visible side (a NO matrix drawn under reversed-Z).
    facingNormal_ = mw;
    facingSign_ = static_cast<double>(robustDirectionSign(clipFromWorld, mode)) *
                  (glm::determinant(glm::dmat3(mx, my, mw)) < 0.0 ? -1.0 : 1.0);
    if (depthClamp_.enabled) {
      // Without near clipping everything in front of the eye is drawn: the rays leave the eye
      // where w grows (dot(mw, d) > 0), wherever the near plane lies.
      facingSign_ = 1.0;
      // The eye: where clip x, y and w vanish (worldFromClip * (0, 0, 1, 0), dehomogenized).
      const glm::dvec4 eye = worldFromClip_[2];
      eye_ = glm::dvec3(eye) / eye.w;
    }
  }
  depthPart_ = worldFromClip_[2] * mode_.nearNdcZ() + worldFromClip_[3] * 1.0;
}

Ray RobustRayGenerator::generate(glm::dvec2 clipXY) const noexcept {
  const double x = clipXY.x;
  const double y = clipXY.y;
  glm::dvec3 d;
  for (int k = 0; k < 3; ++k) {
    d[k] = std::fma(x, myCrossMw_[k], std::fma(y, mwCrossMx_[k], mxCrossMy_[k]));
  }
  const glm::dvec4 nearPointClip(x, y, mode_.nearNdcZ(), 1.0);
  return finishRay(d, worldFromClip_ * nearPointClip);
}

namespace {

// Pixels per block of generateRow: their directions are computed together, then finished.
constexpr std::size_t kRowBlock = 64;

// direction[k][c] = fma(clipX[k], a[c], b[c]): the per-pixel part of generate()'s direction.
// fma is correctly rounded, so the instruction and libm's fma give the same bits; only the call
// differs (a library call per component where the compiler may not assume FMA hardware).
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("fma"))) void directionsWithFmaInstructions(const double* clipX,
                                                                  std::size_t count,
                                                                  const glm::dvec3& a,
                                                                  const glm::dvec3& b,
                                                                  glm::dvec3* direction) {
  for (std::size_t k = 0; k < count; ++k) {
    for (int c = 0; c < 3; ++c) direction[k][c] = __builtin_fma(clipX[k], a[c], b[c]);
  }
}
bool cpuHasFma() {
  static const bool fma = __builtin_cpu_supports("fma");
  return fma;
}
#else
void directionsWithFmaInstructions(const double*, std::size_t, const glm::dvec3&, const glm::dvec3&,
                                   glm::dvec3*) {}
bool cpuHasFma() {
  return false;
}
#endif

void directionsOfRow(const double* clipX, std::size_t count, const glm::dvec3& a,
                     const glm::dvec3& b, glm::dvec3* direction) {
  if (cpuHasFma()) {
    directionsWithFmaInstructions(clipX, count, a, b, direction);
    return;
  }
  for (std::size_t k = 0; k < count; ++k) {
    for (int c = 0; c < 3; ++c) direction[k][c] = std::fma(clipX[k], a[c], b[c]);
  }
}

bool rowKernelsAllowed = true;

#if CLIPRAY_ROW_KERNELS
bool cpuHasAvx2Fma() {
  static const bool avx2Fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return avx2Fma;
}

// What finishRay reads of the generator, and the row's parts of the near point.
struct RowConstants {
  glm::dvec4 column0, rowPart, depthPart;  // near point = (column0 x + rowPart) + depthPart
  glm::dvec3 facingNormal;  // facingSign * dot(facingNormal, d) > 0: see RobustRayGenerator
  glm::dvec4 farPlane;
  double facingSign;
};

// directionsOfRow, structure of arrays (direction[c][k]): the same fma per component.
__attribute__((target("avx2,fma"))) void directionsOfRowSoA(const double* clipX, std::size_t count,
                                                            const glm::dvec3& a,
                                                            const glm::dvec3& b,
                                                            double (*direction)[kRowBlock]) {
  for (int c = 0; c < 3; ++c) {
    const __m256d ac = _mm256_set1_pd(a[c]), bc = _mm256_set1_pd(b[c]);
    std::size_t k = 0;
    for (; k + 4 <= count; k += 4) {
      _mm256_storeu_pd(direction[c] + k, _mm256_fmadd_pd(_mm256_loadu_pd(clipX + k), ac, bc));
    }
    for (; k < count; ++k) direction[c][k] = __builtin_fma(clipX[k], a[c], b[c]);
  }
}

// (A free function: GCC 12 does not give a lambda its enclosing function's target.)
__attribute__((target("avx2"))) inline __m256d bcast(double v) {
  return _mm256_set1_pd(v);
}

// finishRay for the first count4 (a multiple of 4) pixels of a block, four at a time: the same
// operations in the same order (glm's dot products are (x + y) + z and (x + y) + (z + w); division
// and square root are correctly rounded), so the same bits. No FMA in this target: a multiply
// and an add stay two roundings, as in the scalar code.
__attribute__((target("avx2"))) void finishRowBlock(const RowConstants& c, const double* clipX,
                                                    const double (*direction)[kRowBlock],
                                                    std::size_t count4, Ray* rays) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d signBit = bcast(-0.0);
  const __m256d infinity = bcast(std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < count4; k += 4) {
    const __m256d x = _mm256_loadu_pd(clipX + k);
    __m256d n[4];
    for (int r = 0; r < 4; ++r) {
      n[r] =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(bcast(c.column0[r]), x), bcast(c.rowPart[r])),
                        bcast(c.depthPart[r]));
    }
    __m256d d[3];
    for (int r = 0; r < 3; ++r) d[r] = _mm256_loadu_pd(direction[r] + k);
    // Away from the eye (parallel projections: into the frustum through the near plane).
    const __m256d facing =
        _mm256_mul_pd(bcast(c.facingSign),
                      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(bcast(c.facingNormal.x), d[0]),
                                                  _mm256_mul_pd(bcast(c.facingNormal.y), d[1])),
                                    _mm256_mul_pd(bcast(c.facingNormal.z), d[2])));
    const __m256d flip = _mm256_and_pd(_mm256_cmp_pd(facing, zero, _CMP_LT_OQ), signBit);
    for (int r = 0; r < 3; ++r) d[r] = _mm256_xor_pd(d[r], flip);
    const __m256d length = _mm256_sqrt_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1])),
                      _mm256_mul_pd(d[2], d[2])));
    for (int r = 0; r < 3; ++r) d[r] = _mm256_div_pd(d[r], length);
    __m256d o[3];
    for (int r = 0; r < 3; ++r) o[r] = _mm256_div_pd(n[r], n[3]);
    // In front of the eye and finite, else no ray (tMax = kNoRayTMax).
    const __m256d sum = _mm256_add_pd(_mm256_add_pd(o[0], o[1]), o[2]);
    const __m256d valid = _mm256_and_pd(_mm256_cmp_pd(n[3], zero, _CMP_GT_OQ),
                                        _mm256_cmp_pd(_mm256_sub_pd(sum, sum), zero, _CMP_EQ_OQ));
    // Far plane: t = -(F . (o, 1)) / (F.xyz . d), +inf unless finite and positive.
    const __m256d denominator =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(bcast(c.farPlane.x), d[0]),
                                    _mm256_mul_pd(bcast(c.farPlane.y), d[1])),
                      _mm256_mul_pd(bcast(c.farPlane.z), d[2]));
    const __m256d numerator =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(bcast(c.farPlane.x), o[0]),
                                    _mm256_mul_pd(bcast(c.farPlane.y), o[1])),
                      _mm256_add_pd(_mm256_mul_pd(bcast(c.farPlane.z), o[2]),
                                    _mm256_mul_pd(bcast(c.farPlane.w), bcast(1.0))));
    const __m256d t = _mm256_div_pd(_mm256_xor_pd(numerator, signBit), denominator);
    const __m256d farOk = _mm256_and_pd(
        _mm256_cmp_pd(denominator, zero, _CMP_NEQ_OQ),
        _mm256_and_pd(_mm256_cmp_pd(t, zero, _CMP_GT_OQ), _mm256_cmp_pd(t, infinity, _CMP_LT_OQ)));
    const __m256d tMax =
        _mm256_blendv_pd(bcast(kNoRayTMax), _mm256_blendv_pd(infinity, t, farOk), valid);
    simd::storeFourRays({o[0], o[1], o[2], d[0], d[1], d[2], tMax}, rays + k);
  }
}
#endif

}  // namespace

RobustRayGenerator::RowTerms RobustRayGenerator::rowTerms(double clipY) const noexcept {
  // generate() computes d[c] = fma(x, myCrossMw, fma(y, mwCrossMx, mxCrossMy)) and the near point
  // as glm's matrix-vector product ((M0 x + M1 y) + (M2 z + M3 w)): the inner fma, M1 y and
  // (M2 z + M3 w) are the same for the whole row. Computed once, the same operations on the same
  // operands give the same bits.
  RowTerms terms;
  for (int c = 0; c < 3; ++c) terms.direction[c] = std::fma(clipY, mwCrossMx_[c], mxCrossMy_[c]);
  terms.nearPoint = worldFromClip_[1] * clipY;
  return terms;
}

void RobustRayGenerator::generateRow(const RowTerms& row, std::span<const double> clipX,
                                     Ray* rays) const noexcept {
  const glm::dvec3& rowTerm = row.direction;
  const glm::dvec4& rowPart = row.nearPoint;
  const glm::dvec4& depthPart = depthPart_;
#if CLIPRAY_ROW_KERNELS
  if (rowKernelsAllowed && cpuHasAvx2Fma() && simdKernelsChosen()) {
    const RowConstants constants{worldFromClip_[0], rowPart,   depthPart,
                                 facingNormal_,     farPlane_, facingSign_};
    alignas(32) double directions[3][kRowBlock];
    for (std::size_t first = 0; first < clipX.size(); first += kRowBlock) {
      const std::size_t count = std::min(kRowBlock, clipX.size() - first);
      directionsOfRowSoA(clipX.data() + first, count, myCrossMw_, rowTerm, directions);
      const std::size_t count4 = count / 4 * 4;
      finishRowBlock(constants, clipX.data() + first, directions, count4, rays + first);
      // The kernel finishes the rays as finishRay does up to depth clamp's reach and the planes'
      // cut (the tail's finishRay below does its own).
      for (std::size_t k = 0; k < count4 && (depthClamp_.enabled || !clipPlanes_.empty()); ++k) {
        finishInterval(rays[first + k]);
      }
      for (std::size_t k = count4; k < count; ++k) {
        const glm::dvec4 nearPointWorld =
            (worldFromClip_[0] * clipX[first + k] + rowPart) + depthPart;
        rays[first + k] =
            finishRay({directions[0][k], directions[1][k], directions[2][k]}, nearPointWorld);
      }
    }
    return;
  }
#endif
  glm::dvec3 direction[kRowBlock];
  for (std::size_t first = 0; first < clipX.size(); first += kRowBlock) {
    const std::size_t count = std::min(kRowBlock, clipX.size() - first);
    directionsOfRow(clipX.data() + first, count, myCrossMw_, rowTerm, direction);
    for (std::size_t k = 0; k < count; ++k) {
      const glm::dvec4 nearPointWorld =
          (worldFromClip_[0] * clipX[first + k] + rowPart) + depthPart;
      rays[first + k] = finishRay(direction[k], nearPointWorld);
    }
  }
}

void RobustRayGenerator::allowRowKernels(bool allowed) {
  rowKernelsAllowed = allowed;
}

Ray RobustRayGenerator::finishRay(glm::dvec3 d, const glm::dvec4& nearPointWorld) const noexcept {
  // The direction must point away from the eye (parallel: into the frustum through the near
  // plane).
  if (facingSign_ * glm::dot(facingNormal_, d) < 0.0) d = -d;
  d /= std::sqrt(glm::dot(d, d));

  Ray ray;
  ray.origin = glm::dvec3(nearPointWorld) / nearPointWorld.w;
  ray.direction = d;
  // The near point must lie in front of the eye (clip w = 1 / w_world > 0) and be finite. It does
  // not when a matrix is drawn under conventions it was not built for in the reversed sense (a
  // reversed-Z matrix under NO puts z = -1 behind the eye, a NO infinite matrix under reversed-Z
  // puts z = 1 at infinity), nor beyond the horizon of an oblique near plane (Lengyel's water
  // plane: a line of sight pointing below the water meets it behind the eye, and the rasterizer
  // shows nothing there): no ray, rather than one from behind the camera.
  if (!(nearPointWorld.w > 0.0) || !std::isfinite(ray.origin.x + ray.origin.y + ray.origin.z)) {
    ray.tMax = kNoRayTMax;
    finishInterval(ray);  // depth clamp draws this line of sight from the eye all the same
    return ray;
  }

  // Far plane: F . (o + t d, 1) = 0. A zero denominator or a non-positive / non-finite t means the
  // far plane lies at infinity (an infinite-far matrix makes F's xyz exactly zero).
  const double denominator = glm::dot(glm::dvec3(farPlane_), d);
  const double numerator = glm::dot(farPlane_, glm::dvec4(ray.origin, 1.0));
  const double t = -numerator / denominator;
  ray.tMax = (denominator != 0.0 && t > 0.0 && std::isfinite(t))
                 ? t
                 : std::numeric_limits<double>::infinity();
  finishInterval(ray);
  return ray;
}

void RobustRayGenerator::reachForDepthClamp(Ray& ray) const noexcept {
  if (parallel_) {
    ray.origin -= depthClamp_.parallelReach * ray.direction;
  } else {
    ray.origin = eye_;
  }
  ray.tMax = std::numeric_limits<double>::infinity();
  if (depthClamp_.beyondFar) return;
  // The far plane from the new origin, as finishRay finds it from the near point.
  const double denominator = glm::dot(glm::dvec3(farPlane_), ray.direction);
  const double t = -glm::dot(farPlane_, glm::dvec4(ray.origin, 1.0)) / denominator;
  if (denominator != 0.0 && t > 0.0 && std::isfinite(t)) ray.tMax = t;
}

PixelCentreRays::PixelCentreRays(const glm::dmat4& clipFromWorld, DepthMode mode, Viewport viewport,
                                 std::span<const glm::dvec4> clipPlanes, DepthClampRays depthClamp)
    : generator_(clipFromWorld, mode, clipPlanes, depthClamp), viewport_(viewport) {
  clipXOfColumn_.resize(static_cast<std::size_t>(std::max(viewport.width, 0)));
  for (int x = 0; x < viewport.width; ++x) {
    clipXOfColumn_[static_cast<std::size_t>(x)] = clipXYOfPixelCentre(x, 0, viewport).x;
  }
  rowTermsOfRow_.resize(static_cast<std::size_t>(std::max(viewport.height, 0)));
  for (int y = 0; y < viewport.height; ++y) {
    // The same clip y as clipXYOfPixelCentre(x, y): generateRow gives generateForPixel's bits.
    rowTermsOfRow_[static_cast<std::size_t>(y)] =
        generator_.rowTerms(clipXYOfPixelCentre(0, y, viewport).y);
  }
}

void PixelCentreRays::row(int y, int xBegin, int count, Ray* rays) const noexcept {
  generator_.generateRow(
      rowTermsOfRow_[static_cast<std::size_t>(y)],
      std::span<const double>(clipXOfColumn_)
          .subspan(static_cast<std::size_t>(xBegin), static_cast<std::size_t>(count)),
      rays);
}

}  // namespace clipray

#pragma once
// The robust ray method's kernel (internal to rays/): what RayMethods.cpp's generator for
// RayMethod::Robust computes per camera and per pixel, and its AVX2 and AVX-512 rows of float
// rays, which give the kernel's own bits.
//
// Precompute (once per camera and viewport, in __float128 from the entries as given in T):
// with x' = (2i + 1) / W - 1, every per-pixel quantity robust needs is affine in the pixel index:
//   direction  d(i, j) = sign * scale * (x' P + y' Q + R)    P = my x mw, Q = mw x mx, R = mx x my
//   near point N(i, j) = worldFromClip (x', y', z_near, 1)           (homogeneous, 4 components)
//   far dot    F(i, j) = sign * scale * (rowZ - z_far rowW).xyz . (x' P + y' Q + R)
// `sign` makes d point away from the eye, where clip w grows: dot(mw, d) = det(mx, my, mw) > 0, the
// same at every pixel, so the sign is found once and folded into the coefficients. That holds for
// an oblique near plane too (Lengyel's), whose dot with d changes sign at its horizon. A parallel
// projection (mw = 0) takes it from the near plane instead, s * dot(rowZ - z_near rowW, d) > 0
// (s = -1 for reversed-Z): linear in (x', y') and never zero inside the viewport there
// (describeProjection checks the corners), so it too is found at the centre. For a non-oblique
// perspective camera both rules give the same sign. `scale` is a power of two that makes |d|
// about 1 at the viewport's centre: exact, it changes neither the direction nor t_max (F and |d|
// scale alike), and it keeps |d|^2 inside float's range for any matrix float can hold.
//
// Per pixel:
//   direction: d in double, one FMA per component from the row base (d is bilinear in (x', y'),
//              so this is d's exact value up to a few double roundings), |d|^2 in double, then
//              length = sqrt(T(|d|^2)) and inverseLength = 1 / length in T, and
//              direction = T(d * inverseLength) -- ONE rounding to T per component. The scale
//              factor's own error is common to the three components and does not turn the ray,
//              so a float direction is within u_float (+ a few u_double * cond) of the exact one:
//              the cost of storing the exact ray in float, and over a frame of distinct
//              directions the same worst case as rounding the exact ray itself. A parallel
//              projection has one direction for every pixel (P = Q = 0): it is normalized once,
//              in double with a Newton step, and rounded once -- the exact ray rounded to float,
//              not merely within u_float of it (one unlucky rounding would be every pixel's).
//   origin:    N.xyz / N.w, the four forms evaluated in T from a block base (one FMA per pixel
//              from the base of 8 pixels, computed in double, so the increment k < 8 adds
//              almost no rounding);
//   t_max:     (z_far - z_near) |d| / (N.w F)   (seed 002: F_w . n_w = F_c . n_c = z_near - z_far),
//              and +inf when that is not a positive finite number (infinite far plane: F == 0);
//              kNoRayTMax where N.w <= 0 (the line of sight meets the near plane behind the eye:
//              beyond an oblique near plane's horizon, no ray; one compare per pixel).

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/Ray.hpp"
#include "clipray/rays/RayMethods.hpp"

namespace clipray::detail {

struct RobustCoefficients {
  // Affine forms value(i, j) = at0 + i * perI + j * perJ; components: d.xyz, N.xyzw, F.
  double at0[8], perI[8], perJ[8];
  double depthSpan;  // z_far - z_near
};

// The coefficients for a camera (entries as the method received them, widened to double).
RobustCoefficients robustCoefficients(const glm::dmat4& entries, DepthMode mode, Viewport viewport);

template <typename T>
struct RobustKernel {
  static constexpr int kBlock = 8;
  RobustCoefficients coefficients;
  T perI[8];  // the per-pixel increments in T (components 3..7 are used)
  T depthSpan;
  bool constantDirection = false;  // a parallel projection: every pixel's direction is `constant`
  glm::vec<3, T> constant{T(0)};

  RobustKernel(const CameraInputs& in, Viewport viewport) {
    // The entries as the method receives them: rounded to T, then widened exactly.
    const glm::dmat4 entries = glm::dmat4(glm::mat<4, 4, T>(in.clipFromWorld));
    coefficients = robustCoefficients(entries, in.mode, viewport);
    for (int c = 0; c < 8; ++c) perI[c] = T(coefficients.perI[c]);
    depthSpan = T(coefficients.depthSpan);
    constantDirection = true;
    for (int c = 0; c < 3; ++c) {
      constantDirection =
          constantDirection && coefficients.perI[c] == 0.0 && coefficients.perJ[c] == 0.0;
    }
    if (constantDirection) {
      // 1/|d| to ~1e-32 relative (a Newton step from double's), then one rounding to T.
      const double x = coefficients.at0[0], y = coefficients.at0[1], z = coefficients.at0[2];
      const double squared = std::fma(x, x, std::fma(y, y, z * z));
      const double estimate = 1.0 / std::sqrt(squared);
      const double unit = estimate * std::fma(-0.5 * squared, estimate * estimate, 1.5);
      constant = glm::vec<3, T>(T(x * unit), T(y * unit), T(z * unit));
    }
  }

  // The affine forms at the first pixel of row j (double).
  void rowBase(int j, double base[8]) const {
    for (int c = 0; c < 8; ++c) {
      base[c] = std::fma(double(j), coefficients.perJ[c], coefficients.at0[c]);
    }
  }
  // ... and at pixel i0 of that row, rounded to T.
  static void blockBase(const double rowBaseValues[8], const double perIValues[8], int i0,
                        T block[8]) {
    for (int c = 0; c < 8; ++c) block[c] = T(std::fma(double(i0), perIValues[c], rowBaseValues[c]));
  }

  // Pixel i0 + k of the row whose double base is `base`; block holds the T base of pixel i0.
  CameraRay<T> finish(const double base[8], const T block[8], int i0, int k) const {
    const double i = double(i0 + k);
    const double dx = std::fma(i, coefficients.perI[0], base[0]);
    const double dy = std::fma(i, coefficients.perI[1], base[1]);
    const double dz = std::fma(i, coefficients.perI[2], base[2]);
    const T length = std::sqrt(T(std::fma(dx, dx, std::fma(dy, dy, dz * dz))));
    const double inverseLength = double(T(1) / length);
    const T kt = T(k);
    const T nx = std::fma(kt, perI[3], block[3]);
    const T ny = std::fma(kt, perI[4], block[4]);
    const T nz = std::fma(kt, perI[5], block[5]);
    const T nw = std::fma(kt, perI[6], block[6]);
    const T inverseW = T(1) / nw;
    const T farDot = std::fma(kt, perI[7], block[7]);
    const T t = (depthSpan * length) / (nw * farDot);
    CameraRay<T> ray;
    ray.direction = constantDirection ? constant
                                      : glm::vec<3, T>(T(dx * inverseLength), T(dy * inverseLength),
                                                       T(dz * inverseLength));
    ray.origin = {nx * inverseW, ny * inverseW, nz * inverseW};
    ray.tMax = (t > T(0) && t < std::numeric_limits<T>::infinity())
                   ? t
                   : std::numeric_limits<T>::infinity();
    if (!(nw > T(0))) ray.tMax = T(kNoRayTMax);  // near point behind the eye: no ray
    return ray;
  }

  CameraRay<T> operator()(int i, int j) const {
    double base[8];
    rowBase(j, base);
    const int i0 = i & ~(kBlock - 1);
    T block[8];
    blockBase(base, coefficients.perI, i0, block);
    return finish(base, block, i0, i - i0);
  }

  // Portable row: the same arithmetic as operator(), the block base shared by 8 pixels.
  void row(int j, int width, const RaySpan<T>& out) const {
    double base[8];
    rowBase(j, base);
    for (int i0 = 0; i0 < width; i0 += kBlock) {
      T block[8];
      blockBase(base, coefficients.perI, i0, block);
      const int end = std::min(width - i0, kBlock);
      for (int k = 0; k < end; ++k) out.store(i0 + k, finish(base, block, i0, k));
    }
  }
};

#if defined(__x86_64__) || defined(__i386__)
// Row j of float rays, width pixels, 8 per step (AVX2 + FMA, or AVX-512F with them): the caller
// checks that the CPU has them.
void robustRowAvx2(const RobustKernel<float>& kernel, int j, int width, const RaySpan<float>& out);
void robustRowAvx512(const RobustKernel<float>& kernel, int j, int width,
                     const RaySpan<float>& out);
#endif

}  // namespace clipray::detail

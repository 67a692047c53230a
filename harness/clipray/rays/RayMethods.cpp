#include "clipray/rays/RayMethods.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/ext/matrix_projection.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include "clipray/math/Projections.hpp"
#include "clipray/rays/QuadReference.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define CLIPRAY_X86 1
#else
#define CLIPRAY_X86 0
#endif

namespace clipray {

std::string rayMethodName(RayMethod method) {
  switch (method) {
    case RayMethod::UnprojectGlm:
      return "unproject_glm";
    case RayMethod::TwoPoint:
      return "two_point";
    case RayMethod::InversePv:
      return "inverse_pv";
    case RayMethod::FovTangent:
      return "fov_tangent";
    case RayMethod::PlaneCross:
      return "plane_cross";
    case RayMethod::PlaneCrossPre:
      return "plane_cross_pre";
    case RayMethod::Full:
      return "full";
    case RayMethod::Robust:
      return "robust";
  }
  return "?";
}

std::optional<RayMethod> parseRayMethod(std::string_view name) {
  for (const RayMethod method : kRayMethods) {
    if (rayMethodName(method) == name) return method;
  }
  return std::nullopt;
}

bool methodProvidesTMax(RayMethod method) {
  return method != RayMethod::PlaneCross && method != RayMethod::PlaneCrossPre;
}

std::string precisionName(Precision precision) {
  return precision == Precision::Float ? "float" : "double";
}

std::string missingInputs(RayMethod method, const CameraInputs& inputs) {
  if (method == RayMethod::InversePv && (!inputs.clipFromView || !inputs.viewFromWorld)) {
    return "needs the projection and view matrices separately";
  }
  if (method == RayMethod::FovTangent && !inputs.perspective) {
    return "needs fov/aspect/near/far scalars (a symmetric perspective camera)";
  }
  return {};
}

template <typename T>
void RayGenerator<T>::generateGrid(RayBuffer<T>& out) const {
  const int width = viewport_.width;
  out.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(viewport_.height));
  for (int j = 0; j < viewport_.height; ++j) {
    generateRow(j, out.span(static_cast<std::size_t>(j) * static_cast<std::size_t>(width), width));
  }
}

namespace {

constexpr bool kHaveX86 = CLIPRAY_X86 != 0;

bool cpuHasAvx2Fma() {
#if CLIPRAY_X86
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

bool cpuHasAvx512() {
#if CLIPRAY_X86
  static const bool has = cpuHasAvx2Fma() && __builtin_cpu_supports("avx512f");
  return has;
#else
  return false;
#endif
}

std::optional<BatchCodePath> batchCodePathLimit;

BatchCodePath activeBatchCodePath() {
  const BatchCodePath best = cpuHasAvx512()    ? BatchCodePath::Avx512
                             : cpuHasAvx2Fma() ? BatchCodePath::Avx2Fma
                                               : BatchCodePath::Portable;
  return batchCodePathLimit && *batchCodePathLimit < best ? *batchCodePathLimit : best;
}

template <typename T>
using Vec3 = glm::vec<3, T>;
template <typename T>
using Vec4 = glm::vec<4, T>;
template <typename T>
using Mat4 = glm::mat<4, 4, T>;

template <typename T>
T clipX(int i, int width) {
  return T(2 * i + 1) / T(width) - T(1);
}

template <typename T>
Vec3<T> dehomogenize(const Vec4<T>& p) {
  return Vec3<T>(p) / p.w;
}

template <typename T>
Vec3<T> fmaVec(T a, const Vec3<T>& b, const Vec3<T>& c) {
  return {std::fma(a, b.x, c.x), std::fma(a, b.y, c.y), std::fma(a, b.z, c.z)};
}

template <typename T>
Vec3<T> rowXyz(const Mat4<T>& m, int r) {
  return {m[0][r], m[1][r], m[2][r]};
}

// ---- The methods as their sources write them, each a small functor: ray(i, j). ----

// glm::unProjectNO/ZO twice per pixel; glm computes inverse(proj * model) inside every call.
template <typename T>
struct UnprojectGlmKernel {
  Mat4<T> model, projection;
  Vec4<T> viewportRect;
  T nearDepth, farDepth;  // window depth of the near and far plane (reversed-Z swaps them)
  bool zeroToOne;

  UnprojectGlmKernel(const CameraInputs& in, Viewport viewport)
      : model(in.viewFromWorld ? Mat4<T>(*in.viewFromWorld) : Mat4<T>(T(1))),
        projection(in.clipFromView ? Mat4<T>(*in.clipFromView) : Mat4<T>(in.clipFromWorld)),
        viewportRect(T(0), T(0), T(viewport.width), T(viewport.height)),
        nearDepth(in.mode.reversed ? T(1) : T(0)),
        farDepth(in.mode.reversed ? T(0) : T(1)),
        zeroToOne(in.mode.convention == DepthConvention::ZeroToOne) {}

  CameraRay<T> operator()(int i, int j) const {
    const Vec3<T> nearWin(T(i) + T(0.5), T(j) + T(0.5), nearDepth);
    const Vec3<T> farWin(T(i) + T(0.5), T(j) + T(0.5), farDepth);
    const Vec3<T> a = zeroToOne ? glm::unProjectZO(nearWin, model, projection, viewportRect)
                                : glm::unProjectNO(nearWin, model, projection, viewportRect);
    const Vec3<T> b = zeroToOne ? glm::unProjectZO(farWin, model, projection, viewportRect)
                                : glm::unProjectNO(farWin, model, projection, viewportRect);
    const Vec3<T> delta = b - a;
    const T length = glm::length(delta);
    return {a, delta / length, length};
  }
};

// worldFromClip once (in T, as a float app would); near and far point; normalize(far - near).
template <typename T>
struct TwoPointKernel {
  Mat4<T> worldFromClip;
  T zNear, zFar;
  int width, height;

  TwoPointKernel(const CameraInputs& in, Viewport viewport)
      : worldFromClip(glm::inverse(Mat4<T>(in.clipFromWorld))),
        zNear(T(in.mode.nearNdcZ())),
        zFar(T(in.mode.farNdcZ())),
        width(viewport.width),
        height(viewport.height) {}

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> a = dehomogenize(worldFromClip * Vec4<T>(x, y, zNear, T(1)));
    const Vec3<T> b = dehomogenize(worldFromClip * Vec4<T>(x, y, zFar, T(1)));
    const Vec3<T> delta = b - a;
    const T length = glm::length(delta);
    return {a, delta / length, length};
  }
};

// Seeds 000/001: viewFromClip * (x', y', z_n, 1), w := 0, then worldFromView. The origin is the
// near point through the same two inverses, t_max the distance to the far point.
template <typename T>
struct InversePvKernel {
  Mat4<T> viewFromClip, worldFromView;
  T zNear, zFar;
  int width, height;

  InversePvKernel(const CameraInputs& in, Viewport viewport)
      : viewFromClip(glm::inverse(Mat4<T>(*in.clipFromView))),
        worldFromView(glm::inverse(Mat4<T>(*in.viewFromWorld))),
        zNear(T(in.mode.nearNdcZ())),
        zFar(T(in.mode.farNdcZ())),
        width(viewport.width),
        height(viewport.height) {}

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec4<T> nearView = viewFromClip * Vec4<T>(x, y, zNear, T(1));
    const Vec3<T> direction =
        glm::normalize(Vec3<T>(worldFromView * Vec4<T>(Vec3<T>(nearView), T(0))));
    const Vec3<T> origin = Vec3<T>(worldFromView * Vec4<T>(dehomogenize(nearView), T(1)));
    const Vec4<T> farView = viewFromClip * Vec4<T>(x, y, zFar, T(1));
    const Vec3<T> farPoint = Vec3<T>(worldFromView * Vec4<T>(dehomogenize(farView), T(1)));
    return {origin, direction, glm::length(farPoint - origin)};
  }
};

// Seed 003: slopes from tan(fov / 2) and the aspect, in view space, rotated to world space by the
// inverse view matrix; origin on the near plane, t_max to the far plane.
template <typename T>
struct FovTangentKernel {
  T slopeX, slopeY, nearDistance, depth;
  Mat4<T> worldFromView;
  int width, height;

  FovTangentKernel(const CameraInputs& in, Viewport viewport)
      : worldFromView(Mat4<T>(in.perspective->worldFromView)),
        width(viewport.width),
        height(viewport.height) {
    const PerspectiveScalars& s = *in.perspective;
    const T tangent = std::tan(T(s.fovYRadians) * T(0.5));
    slopeX = tangent * T(s.aspect);
    slopeY = tangent;
    nearDistance = T(s.nearDistance);
    depth = T(s.farDistance) - T(s.nearDistance);  // +inf for an infinite far plane
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> slope = Vec3<T>(worldFromView * Vec4<T>(x * slopeX, y * slopeY, T(-1), T(0)));
    const Vec3<T> eye(worldFromView[3]);
    const T length = glm::length(slope);
    return {eye + nearDistance * slope, slope / length, depth * length};
  }
};

// Listing 1's origin (near point through worldFromClip), shared by the two direction listings.
template <typename T>
struct ListingOneOrigin {
  Mat4<T> worldFromClip;
  T zNear;
  explicit ListingOneOrigin(const CameraInputs& in)
      : worldFromClip(glm::inverse(Mat4<T>(in.clipFromWorld))), zNear(T(in.mode.nearNdcZ())) {}
  Vec3<T> operator()(T x, T y) const {
    return dehomogenize(worldFromClip * Vec4<T>(x, y, zNear, T(1)));
  }
};

// Listing 2: u = fma(-x, mw, mx), v = fma(-y, mw, my), d = cross(u, v). No sign fix, no t_max.
template <typename T>
struct PlaneCrossKernel {
  Vec3<T> mx, my, mw;
  ListingOneOrigin<T> origin;
  int width, height;

  PlaneCrossKernel(const CameraInputs& in, Viewport viewport)
      : origin(in), width(viewport.width), height(viewport.height) {
    const Mat4<T> m(in.clipFromWorld);
    mx = rowXyz(m, 0);
    my = rowXyz(m, 1);
    mw = rowXyz(m, 3);
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> d = glm::cross(fmaVec(-x, mw, mx), fmaVec(-y, mw, my));
    return {origin(x, y), glm::normalize(d), std::numeric_limits<T>::infinity()};
  }
};

// Listing 3: three cross products precomputed (in T), then d = fma(x, my_mw, mx_my),
// d = fma(y, mw_mx, d).
template <typename T>
struct PlaneCrossPreKernel {
  Vec3<T> myCrossMw, mwCrossMx, mxCrossMy;
  ListingOneOrigin<T> origin;
  int width, height;

  PlaneCrossPreKernel(const CameraInputs& in, Viewport viewport)
      : origin(in), width(viewport.width), height(viewport.height) {
    const Mat4<T> m(in.clipFromWorld);
    const Vec3<T> mx = rowXyz(m, 0), my = rowXyz(m, 1), mw = rowXyz(m, 3);
    myCrossMw = glm::cross(my, mw);
    mwCrossMx = glm::cross(mw, mx);
    mxCrossMy = glm::cross(mx, my);
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> d = fmaVec(y, mwCrossMx, fmaVec(x, myCrossMw, mxCrossMy));
    return {origin(x, y), glm::normalize(d), std::numeric_limits<T>::infinity()};
  }
};

// Listing 4 as published, with z_n set to the near plane of the convention (the listing's comment
// invites that) and the far plane left at z' = 1 as written. Known failures: with an infinite far
// plane dot(mw - mz, d) is exactly zero and the sign of that zero decides the ray's sign; with
// reversed-Z the far plane is z' = 0, not 1.
template <typename T>
struct FullKernel {
  Mat4<T> worldFromClip;
  Vec3<T> mx, my, mz, mw;
  T zNear;
  int width, height;

  FullKernel(const CameraInputs& in, Viewport viewport)
      : worldFromClip(glm::inverse(Mat4<T>(in.clipFromWorld))),
        zNear(T(in.mode.nearNdcZ())),
        width(viewport.width),
        height(viewport.height) {
    const Mat4<T> m(in.clipFromWorld);
    mx = rowXyz(m, 0);
    my = rowXyz(m, 1);
    mz = rowXyz(m, 2);
    mw = rowXyz(m, 3);
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec4<T> nw = worldFromClip * Vec4<T>(x, y, zNear, T(1));
    const T nFac = T(1) / nw.w;
    const Vec3<T> origin = Vec3<T>(nw) * nFac;
    const Vec3<T> d = glm::cross(fmaVec(-x, mw, mx), fmaVec(-y, mw, my));
    T dFac = T(1) / std::sqrt(glm::dot(d, d));
    const T num = T(1) - zNear;
    const T den = glm::dot(mw - mz, d);
    T tMax = -nFac * num / (dFac * den);
    dFac = tMax > T(0) ? dFac : -dFac;
    tMax = std::abs(tMax);
    return {origin, d * dFac, tMax};
  }
};

// ---- robust ----
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
struct RobustCoefficients {
  // Affine forms value(i, j) = at0 + i * perI + j * perJ; components: d.xyz, N.xyzw, F.
  double at0[8], perI[8], perJ[8];
  double depthSpan;  // z_far - z_near
};

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

template <typename T>
struct RobustKernel {
  static constexpr int kBlock = 8;
  RobustCoefficients coefficients;
  T perI[8];  // the per-pixel increments in T (components 3..7 are used)
  T depthSpan;
  bool constantDirection = false;  // a parallel projection: every pixel's direction is `constant`
  Vec3<T> constant{T(0)};

  RobustKernel(const CameraInputs& in, Viewport viewport) {
    // The entries as the method receives them: rounded to T, then widened exactly.
    const glm::dmat4 entries = glm::dmat4(Mat4<T>(in.clipFromWorld));
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
      constant = Vec3<T>(T(x * unit), T(y * unit), T(z * unit));
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
                                      : Vec3<T>(T(dx * inverseLength), T(dy * inverseLength),
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

#if CLIPRAY_X86
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

// 8 double lanes rounded to 8 float lanes. The masked form (all lanes) because GCC 12's unmasked
// intrinsic trips -Wmaybe-uninitialized inside its own header.
__attribute__((target("avx512f,avx2,fma"))) inline __m256 toFloat8(__m512d lanes) {
  return _mm512_mask_cvtpd_ps(_mm256_setzero_ps(), 0xFF, lanes);
}

// The same row with the direction's 8 pixels in one register of 8 double lanes (AVX-512F): the
// same operations, so the same bits, in fewer instructions (no halves to split and join).
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

// The other methods' rows, compiled a second time with FMA and AVX2 enabled so their std::fma
// calls become instructions (the comparison with robust stays fair); chosen at run time.
template <typename Kernel, typename T>
__attribute__((target("avx2,fma"))) void rowLoopAvx2(const Kernel& kernel, int j, int width,
                                                     const RaySpan<T>& out) {
  for (int i = 0; i < width; ++i) out.store(i, kernel(i, j));
}
#endif

template <typename Kernel, typename T>
void rowLoopPortable(const Kernel& kernel, int j, int width, const RaySpan<T>& out) {
  for (int i = 0; i < width; ++i) out.store(i, kernel(i, j));
}

template <typename T, typename Kernel>
class KernelGenerator final : public RayGenerator<T> {
 public:
  KernelGenerator(const CameraInputs& inputs, Viewport viewport)
      : RayGenerator<T>(viewport),
        kernel_(inputs, viewport),
        fast_(activeBatchCodePath() >= BatchCodePath::Avx2Fma),
        avx512_(activeBatchCodePath() == BatchCodePath::Avx512) {}

  CameraRay<T> pixelRay(int i, int j) const noexcept override { return kernel_(i, j); }

  void generateRow(int j, const RaySpan<T>& out) const noexcept override {
    const int width = this->viewport().width;
#if CLIPRAY_X86
    if (fast_) {
      if constexpr (std::is_same_v<Kernel, RobustKernel<float>>) {
        if (avx512_) {
          robustRowAvx512(kernel_, j, width, out);
        } else {
          robustRowAvx2(kernel_, j, width, out);
        }
      } else {
        rowLoopAvx2(kernel_, j, width, out);
      }
      return;
    }
#endif
    if constexpr (std::is_same_v<Kernel, RobustKernel<T>>) {
      kernel_.row(j, width, out);
    } else {
      rowLoopPortable(kernel_, j, width, out);
    }
  }

 private:
  Kernel kernel_;
  bool fast_;
  bool avx512_;
};

template <typename T, typename Kernel>
std::unique_ptr<RayGenerator<T>> make(const CameraInputs& inputs, Viewport viewport) {
  return std::make_unique<KernelGenerator<T, Kernel>>(inputs, viewport);
}

}  // namespace

template <typename T>
std::unique_ptr<RayGenerator<T>> makeRayGenerator(RayMethod method, const CameraInputs& inputs,
                                                  Viewport viewport) {
  if (!missingInputs(method, inputs).empty()) return nullptr;
  switch (method) {
    case RayMethod::UnprojectGlm:
      return make<T, UnprojectGlmKernel<T>>(inputs, viewport);
    case RayMethod::TwoPoint:
      return make<T, TwoPointKernel<T>>(inputs, viewport);
    case RayMethod::InversePv:
      return make<T, InversePvKernel<T>>(inputs, viewport);
    case RayMethod::FovTangent:
      return make<T, FovTangentKernel<T>>(inputs, viewport);
    case RayMethod::PlaneCross:
      return make<T, PlaneCrossKernel<T>>(inputs, viewport);
    case RayMethod::PlaneCrossPre:
      return make<T, PlaneCrossPreKernel<T>>(inputs, viewport);
    case RayMethod::Full:
      return make<T, FullKernel<T>>(inputs, viewport);
    case RayMethod::Robust:
      return make<T, RobustKernel<T>>(inputs, viewport);
  }
  return nullptr;
}

std::string batchCodePathName(BatchCodePath path) {
  switch (path) {
    case BatchCodePath::Portable:
      return "portable";
    case BatchCodePath::Avx2Fma:
      return "avx2+fma";
    case BatchCodePath::Avx512:
      return "avx512f+avx2+fma";
  }
  return "?";
}

std::vector<BatchCodePath> supportedBatchCodePaths() {
  std::vector<BatchCodePath> paths = {BatchCodePath::Portable};
  if (kHaveX86 && cpuHasAvx2Fma()) paths.push_back(BatchCodePath::Avx2Fma);
  if (kHaveX86 && cpuHasAvx512()) paths.push_back(BatchCodePath::Avx512);
  return paths;
}

void limitBatchCodePath(std::optional<BatchCodePath> limit) {
  batchCodePathLimit = limit;
}

std::string batchCodePath() {
  return batchCodePathName(activeBatchCodePath());
}

template class RayGenerator<float>;
template class RayGenerator<double>;
template std::unique_ptr<RayGenerator<float>> makeRayGenerator<float>(RayMethod,
                                                                      const CameraInputs&,
                                                                      Viewport);
template std::unique_ptr<RayGenerator<double>> makeRayGenerator<double>(RayMethod,
                                                                        const CameraInputs&,
                                                                        Viewport);

}  // namespace clipray

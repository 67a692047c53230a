#pragma once
// bgfx's camera math (bx), written from bkaradzic/bx:
//   src/math.cpp               mtxLookAt, mtxProj (fovy / aspect, and bounds form), mtxProjInf
//                              (NearFar::Reverse), mtxOrtho, all with Handedness (default Left)
//   include/bx/math.h          Handedness {Left, Right}, NearFar {Default, Reverse}, defaults
//   include/bx/inline/math.inl toRad = deg * kPi / 180, normalize = v * (1 / length), dot, cross
// bx writes 16 floats that bgfx uploads as is (setViewTransform / setUniform); in GLSL, bgfx's
// mul(u_viewProj, v) is u_viewProj * v and the uniform is uploaded with transpose = GL_FALSE, so a
// GL shader sees this array as a column-major mat4 with column vectors: the GL array as is.
// homogeneousNdc = bgfx::getCaps()->homogeneousDepth: true on OpenGL (NO), false on D3D, Vulkan,
// Metal (ZO).
//
// Precision: bx computes in float, and its tan is bx::sin / bx::cos, polynomial approximations
// (relative error ~1e-7), reproduced here for T = float; T = double uses std::tan and the double
// pi. The fovy of mtxProj is in degrees (the code calls toRad), although math.h documents radians.
//
// Default handedness is LEFT (view looks down +z): a bgfx app using bx defaults in a world it
// reads as right-handed sees a mirrored image; bx's LH conventions assume a left-handed world.

#include <cmath>
#include <numbers>
#include <type_traits>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::bgfx {

enum class NearFar { Default, Reverse };

namespace detail {

// bx::kPi is the float 3.1415926535897932384626433832795f; a double build (which bx does not
// have) uses the double pi so that its fov carries no float rounding.
template <class T>
constexpr T kPi = std::is_same_v<T, float> ? static_cast<T>(3.1415926535897932384626433832795f)
                                           : static_cast<T>(std::numbers::pi);

template <class T>
T toRad(T deg) {
  return deg * kPi<T> / T(180);
}

// bx::floor, bx::cos (minimax polynomials after reduction by pi / 2), bx::sin = cos(a - pi / 2),
// bx::tan = sin / cos (include/bx/inline/math.inl), for float; the C library for double.
inline float bxFloor(float a) {
  auto trunc = [](float v) { return float(int(v)); };
  if (a < 0.0f) {
    const float fr = -a - trunc(-a);
    const float tr = trunc(-a);
    return -tr - float(0.0f != fr);
  }
  return a - (a - trunc(a));
}

inline float bxCos(float a) {
  constexpr float kInvPi = 1.0f / 3.1415926535897932384626433832795f;
  constexpr float kPiHalf = 1.5707963267948966192313216916398f;
  const float scaled = a * 2.0f * kInvPi;
  const float real = bxFloor(scaled);
  const float xx = a - real * kPiHalf;
  const int bits = int(real) & 3;
  const bool cosine = bits == 0 || bits == 2;
  const float c0 = cosine ? 1.0f : xx;
  const float c2 = cosine ? -0.5f : -0.16666667163372039794921875f;
  const float c4 = cosine ? 4.166664183139801025390625e-2f : 8.333347737789154052734375e-3f;
  const float c6 =
      cosine ? -1.388833043165504932403564453125e-3f : -1.9842604524455964565277099609375e-4f;
  const float c8 =
      cosine ? 2.47562347794882953166961669921875e-5f : 2.760012648650445044040679931640625e-6f;
  const float c10 = cosine ? -2.59630184018533327616751194000244140625e-7f
                           : -2.50293279435709337121807038784027099609375e-8f;
  const float xsq = xx * xx;
  const float tmp0 = c10 * xsq + c8;
  const float tmp1 = tmp0 * xsq + c6;
  const float tmp2 = tmp1 * xsq + c4;
  const float tmp3 = tmp2 * xsq + c2;
  const float tmp4 = tmp3 * xsq + 1.0f;
  const float result = tmp4 * c0;
  return bits == 1 || bits == 2 ? -result : result;
}

template <class T>
T tan(T a) {
  if constexpr (std::is_same_v<T, float>)
    return bxCos(a - 1.5707963267948966192313216916398f) / bxCos(a);
  else
    return std::tan(a);
}

template <class T>
Mat4 projXYWH(T x, T y, T width, T height, T near, T far, bool homogeneousNdc, Handedness hand) {
  const T diff = far - near;
  const T aa = homogeneousNdc ? (far + near) / diff : far / diff;
  const T bb = homogeneousNdc ? (T(2) * far * near) / diff : near * aa;
  const bool rh = hand == Handedness::Right;
  Mat4T<T> r = zeroT<T>();
  r[0] = width;
  r[5] = height;
  r[8] = rh ? x : -x;
  r[9] = rh ? y : -y;
  r[10] = rh ? -aa : aa;
  r[11] = rh ? T(-1) : T(1);
  r[14] = -bb;
  return toMat4(r);
}

template <class T>
Mat4 projInfXYWH(T x, T y, T width, T height, T near, bool homogeneousNdc, Handedness hand,
                 NearFar nearFar) {
  T aa, bb;
  if (nearFar == NearFar::Reverse) {
    aa = homogeneousNdc ? T(-1) : T(0);
    bb = homogeneousNdc ? T(-2) * near : -near;
  } else {
    aa = T(1);
    bb = homogeneousNdc ? T(2) * near : near;
  }
  const bool rh = hand == Handedness::Right;
  Mat4T<T> r = zeroT<T>();
  r[0] = width;
  r[5] = height;
  r[8] = rh ? x : -x;
  r[9] = rh ? y : -y;
  r[10] = rh ? -aa : aa;
  r[11] = rh ? T(-1) : T(1);
  r[14] = -bb;
  return toMat4(r);
}

}  // namespace detail

// bx::mtxProj(result, fovy (degrees), aspect, near, far, homogeneousNdc, handedness).
// NO when homogeneousNdc (OpenGL), ZO otherwise; LH by default (w = +z), RH with
// Handedness::Right (w = -z); finite far; not reversed; column vectors as uploaded.
template <class T>
Mat4 mtxProj(T fovy, T aspect, T near, T far, bool homogeneousNdc,
             Handedness hand = Handedness::Left) {
  const T height = T(1) / detail::tan(detail::toRad(fovy) * T(0.5));
  const T width = height * T(1) / aspect;
  return detail::projXYWH<T>(T(0), T(0), width, height, near, far, homogeneousNdc, hand);
}

// bx::mtxProj(result, ut, dt, lt, rt, near, far, homogeneousNdc, handedness): asymmetric frustum.
// bx documents ut, dt, lt, rt as the tangents of the up / down / left / right angles, but its
// arithmetic (width = 2 near / (rt - lt), x offset (rt + lt) / (rt - lt)) treats them as signed
// window bounds on the near plane, like glFrustum's (right = rt, left = lt, top = ut, bottom =
// dt): they are tangents only when near = 1. Depth and handedness as mtxProj; off-axis when
// ut != -dt or lt != -rt.
template <class T>
Mat4 mtxProjBounds(T ut, T dt, T lt, T rt, T near, T far, bool homogeneousNdc,
                   Handedness hand = Handedness::Left) {
  const T invDiffRl = T(1) / (rt - lt);
  const T invDiffUd = T(1) / (ut - dt);
  const T width = T(2) * near * invDiffRl;
  const T height = T(2) * near * invDiffUd;
  const T xx = (rt + lt) * invDiffRl;
  const T yy = (ut + dt) * invDiffUd;
  return detail::projXYWH<T>(xx, yy, width, height, near, far, homogeneousNdc, hand);
}

// bx::mtxProjInf(result, fovy (degrees), aspect, near, homogeneousNdc, handedness, nearFar):
// infinite far. NearFar::Default: NO / ZO as homogeneousNdc, not reversed. NearFar::Reverse:
// reversed (near -> +1, infinity -> 0 for ZO; near -> +1, infinity -> -1 for NO). Handedness as
// mtxProj; column vectors.
template <class T>
Mat4 mtxProjInf(T fovy, T aspect, T near, bool homogeneousNdc, Handedness hand = Handedness::Left,
                NearFar nearFar = NearFar::Default) {
  const T height = T(1) / detail::tan(detail::toRad(fovy) * T(0.5));
  const T width = height * T(1) / aspect;
  return detail::projInfXYWH<T>(T(0), T(0), width, height, near, homogeneousNdc, hand, nearFar);
}

// bx::mtxOrtho(result, left, right, bottom, top, near, far, offset, homogeneousNdc, handedness).
// w = 1; NO / ZO as homogeneousNdc; LH by default; offset is added to clip x (bgfx uses it for
// stereo); column vectors.
template <class T>
Mat4 mtxOrtho(T left, T right, T bottom, T top, T near, T far, T offset, bool homogeneousNdc,
              Handedness hand = Handedness::Left) {
  const T aa = T(2) / (right - left);
  const T bb = T(2) / (top - bottom);
  const T cc = (homogeneousNdc ? T(2) : T(1)) / (far - near);
  const T dd = (left + right) / (left - right);
  const T ee = (top + bottom) / (bottom - top);
  const T ff = homogeneousNdc ? (near + far) / (near - far) : near / (near - far);
  Mat4T<T> r = zeroT<T>();
  r[0] = aa;
  r[5] = bb;
  r[10] = hand == Handedness::Right ? -cc : cc;
  r[12] = dd + offset;
  r[13] = ee;
  r[14] = ff;
  r[15] = T(1);
  return toMat4(r);
}

// bx::mtxLookAt(result, eye, at, up = {0, 1, 0}, handedness = Left). LH: view = normalize(at -
// eye) becomes +z; RH: view = normalize(eye - at) becomes +z (camera looks down -z). right =
// normalize(cross(up, view)), up' = cross(view, right). Column vectors as uploaded.
template <class T>
Mat4 mtxLookAt(Vec3T<T> eye, Vec3T<T> at, Vec3T<T> up = {T(0), T(1), T(0)},
               Handedness hand = Handedness::Left) {
  auto dot = [](Vec3T<T> a, Vec3T<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  auto cross = [](Vec3T<T> a, Vec3T<T> b) {
    return Vec3T<T>{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  auto normalize = [&](Vec3T<T> a) {  // divSafe(a, length(a)) = a * rcpSafe(length)
    const T inv = T(1) / std::sqrt(dot(a, a));
    return Vec3T<T>{a.x * inv, a.y * inv, a.z * inv};
  };
  const Vec3T<T> view =
      normalize(hand == Handedness::Right ? Vec3T<T>{eye.x - at.x, eye.y - at.y, eye.z - at.z}
                                          : Vec3T<T>{at.x - eye.x, at.y - eye.y, at.z - eye.z});
  const Vec3T<T> uxv = cross(up, view);
  const Vec3T<T> right = dot(uxv, uxv) == T(0)
                             ? Vec3T<T>{hand == Handedness::Left ? T(-1) : T(1), T(0), T(0)}
                             : normalize(uxv);
  const Vec3T<T> up2 = cross(view, right);
  Mat4T<T> r = zeroT<T>();
  r[0] = right.x;
  r[1] = up2.x;
  r[2] = view.x;
  r[4] = right.y;
  r[5] = up2.y;
  r[6] = view.y;
  r[8] = right.z;
  r[9] = up2.z;
  r[10] = view.z;
  r[12] = -dot(right, eye);
  r[13] = -dot(up2, eye);
  r[14] = -dot(view, eye);
  r[15] = T(1);
  return toMat4(r);
}

}  // namespace clipray::testing::engines::bgfx

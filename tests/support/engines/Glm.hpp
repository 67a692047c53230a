#pragma once
// GLM's projection and view matrices, written from g-truc/glm (glm 1.0.x):
//   glm/ext/matrix_clip_space.inl  (perspective*, perspectiveFov*, infinitePerspective*, frustum*,
//                                   ortho*)
//   glm/ext/matrix_transform.inl   (lookAtRH, lookAtLH)
//   glm/detail/func_geometric.inl  (normalize = v * inversesqrt(dot(v, v)), dot, cross)
//   glm/detail/type_mat4x4.inl     (operator*: see multiplyT in Common.hpp)
// Same operation order as glm with GLM_FORCE_INTRINSICS off (its default), so float and double
// builds match glm bit for bit. glm matrices are column-major (Result[col][row]) with column
// vectors, so the result is the GL array as is. Angles in radians (GLM_FORCE_RADIANS is the only
// mode since 0.9.6).
//
// Naming: RH = view space looks down -z (w_clip = -z_view); LH = looks down +z (w_clip = +z_view).
// NO = z_ndc in [-1, 1]; ZO = z_ndc in [0, 1]. None of them is reversed; none expects row vectors.
//
// Version note: glm 0.9.9.x (Debian's libglm-dev 0.9.9.8) writes frustumLH_* with
// Result[2][0] = +(r + l) / (r - l) and Result[2][1] = +(t + b) / (t - b); glm 1.0 negates them,
// which is the correct off-axis LH frustum (the 0.9.9 one puts the window on the mirrored side).
// The functions below follow glm 1.0. glm 0.9.9 also lacks infinitePerspective{RH,LH}_{NO,ZO}
// (its infinitePerspectiveRH / LH are the _NO forms).
//
// The namespace is glmx, not glm, so that it never shadows ::glm in a test that uses both.

#include <cmath>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::glmx {

namespace detail {

template <class T>
constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;  // compute_dot<vec<3>>: tmp = a * b; x + y + z
}

template <class T>
constexpr Vec3T<T> cross(const Vec3T<T>& x, const Vec3T<T>& y) {
  return {x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y};
}

template <class T>
Vec3T<T> normalize(const Vec3T<T>& v) {
  const T s = T(1) / std::sqrt(dot(v, v));  // inversesqrt(x) = 1 / sqrt(x)
  return {v.x * s, v.y * s, v.z * s};
}

template <class T>
constexpr Vec3T<T> sub(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}

// Shared tail of the perspective family: only [0][0], [1][1] and the z/w entries are set.
template <class T>
Mat4T<T> perspectiveTail(T sx, T sy, T zNear, T zFar, bool rightHanded, bool zeroToOne) {
  Mat4T<T> m = zeroT<T>();
  el(m, 0, 0) = sx;
  el(m, 1, 1) = sy;
  if (rightHanded) {
    el(m, 2, 2) = zeroToOne ? zFar / (zNear - zFar) : -(zFar + zNear) / (zFar - zNear);
    el(m, 2, 3) = -T(1);
  } else {
    el(m, 2, 2) = zeroToOne ? zFar / (zFar - zNear) : (zFar + zNear) / (zFar - zNear);
    el(m, 2, 3) = T(1);
  }
  el(m, 3, 2) =
      zeroToOne ? -(zFar * zNear) / (zFar - zNear) : -(T(2) * zFar * zNear) / (zFar - zNear);
  return m;
}

template <class T>
Mat4T<T> perspective(T fovy, T aspect, T zNear, T zFar, bool rh, bool zo) {
  const T tanHalfFovy = std::tan(fovy / T(2));
  return perspectiveTail<T>(T(1) / (aspect * tanHalfFovy), T(1) / (tanHalfFovy), zNear, zFar, rh,
                            zo);
}

template <class T>
Mat4T<T> perspectiveFov(T fov, T width, T height, T zNear, T zFar, bool rh, bool zo) {
  const T rad = fov;
  const T h = std::cos(T(0.5) * rad) / std::sin(T(0.5) * rad);
  const T w = h * height / width;
  return perspectiveTail<T>(w, h, zNear, zFar, rh, zo);
}

template <class T>
Mat4T<T> infinitePerspective(T fovy, T aspect, T zNear, bool rh, bool zo) {
  const T range = std::tan(fovy / T(2)) * zNear;
  const T left = -range * aspect;
  const T right = range * aspect;
  const T bottom = -range;
  const T top = range;
  Mat4T<T> m = zeroT<T>();
  el(m, 0, 0) = (T(2) * zNear) / (right - left);
  el(m, 1, 1) = (T(2) * zNear) / (top - bottom);
  el(m, 2, 2) = rh ? -T(1) : T(1);
  el(m, 2, 3) = rh ? -T(1) : T(1);
  el(m, 3, 2) = zo ? -zNear : -T(2) * zNear;
  return m;
}

template <class T>
Mat4T<T> frustum(T left, T right, T bottom, T top, T nearVal, T farVal, bool rh, bool zo) {
  Mat4T<T> m = zeroT<T>();
  el(m, 0, 0) = (T(2) * nearVal) / (right - left);
  el(m, 1, 1) = (T(2) * nearVal) / (top - bottom);
  el(m, 2, 0) = rh ? (right + left) / (right - left) : -(right + left) / (right - left);
  el(m, 2, 1) = rh ? (top + bottom) / (top - bottom) : -(top + bottom) / (top - bottom);
  if (rh) {
    el(m, 2, 2) = zo ? farVal / (nearVal - farVal) : -(farVal + nearVal) / (farVal - nearVal);
    el(m, 2, 3) = T(-1);
  } else {
    el(m, 2, 2) = zo ? farVal / (farVal - nearVal) : (farVal + nearVal) / (farVal - nearVal);
    el(m, 2, 3) = T(1);
  }
  el(m, 3, 2) = zo ? -(farVal * nearVal) / (farVal - nearVal)
                   : -(T(2) * farVal * nearVal) / (farVal - nearVal);
  return m;
}

template <class T>
Mat4T<T> ortho(T left, T right, T bottom, T top, T zNear, T zFar, bool rh, bool zo) {
  Mat4T<T> m = identityT<T>();
  el(m, 0, 0) = T(2) / (right - left);
  el(m, 1, 1) = T(2) / (top - bottom);
  if (rh)
    el(m, 2, 2) = zo ? -T(1) / (zFar - zNear) : -T(2) / (zFar - zNear);
  else
    el(m, 2, 2) = zo ? T(1) / (zFar - zNear) : T(2) / (zFar - zNear);
  el(m, 3, 0) = -(right + left) / (right - left);
  el(m, 3, 1) = -(top + bottom) / (top - bottom);
  el(m, 3, 2) = zo ? -zNear / (zFar - zNear) : -(zFar + zNear) / (zFar - zNear);
  return m;
}

}  // namespace detail

// --- perspective(fovy, aspect, near, far): fovy in radians, symmetric, finite far. ---

// NO, RH, finite far, column vectors. The GL default (glm::perspective without clip-control
// defines).
template <class T>
Mat4 perspectiveRH_NO(T fovy, T aspect, T zNear, T zFar) {
  return toMat4(detail::perspective<T>(fovy, aspect, zNear, zFar, true, false));
}
// ZO, RH, finite far, column vectors (Vulkan / glClipControl apps; pair with vulkanYFlip for
// Vulkan's y-down clip space).
template <class T>
Mat4 perspectiveRH_ZO(T fovy, T aspect, T zNear, T zFar) {
  return toMat4(detail::perspective<T>(fovy, aspect, zNear, zFar, true, true));
}
// NO, LH (view looks down +z), finite far, column vectors.
template <class T>
Mat4 perspectiveLH_NO(T fovy, T aspect, T zNear, T zFar) {
  return toMat4(detail::perspective<T>(fovy, aspect, zNear, zFar, false, false));
}
// ZO, LH, finite far, column vectors (the D3D convention; equals XMMatrixPerspectiveFovLH up to
// DirectXMath's sin/cos approximation).
template <class T>
Mat4 perspectiveLH_ZO(T fovy, T aspect, T zNear, T zFar) {
  return toMat4(detail::perspective<T>(fovy, aspect, zNear, zFar, false, true));
}

// --- perspectiveFov(fov, width, height, near, far): fov (vertical) in radians; cot via cos/sin. -

// NO, RH, finite far, column vectors.
template <class T>
Mat4 perspectiveFovRH_NO(T fov, T width, T height, T zNear, T zFar) {
  return toMat4(detail::perspectiveFov<T>(fov, width, height, zNear, zFar, true, false));
}
// ZO, RH, finite far, column vectors.
template <class T>
Mat4 perspectiveFovRH_ZO(T fov, T width, T height, T zNear, T zFar) {
  return toMat4(detail::perspectiveFov<T>(fov, width, height, zNear, zFar, true, true));
}
// NO, LH, finite far, column vectors.
template <class T>
Mat4 perspectiveFovLH_NO(T fov, T width, T height, T zNear, T zFar) {
  return toMat4(detail::perspectiveFov<T>(fov, width, height, zNear, zFar, false, false));
}
// ZO, LH, finite far, column vectors.
template <class T>
Mat4 perspectiveFovLH_ZO(T fov, T width, T height, T zNear, T zFar) {
  return toMat4(detail::perspectiveFov<T>(fov, width, height, zNear, zFar, false, true));
}

// --- infinitePerspective(fovy, aspect, near): far plane at infinity, not reversed. ---

// NO, RH, infinite far, column vectors (glm 0.9.9's infinitePerspectiveRH).
template <class T>
Mat4 infinitePerspectiveRH_NO(T fovy, T aspect, T zNear) {
  return toMat4(detail::infinitePerspective<T>(fovy, aspect, zNear, true, false));
}
// ZO, RH, infinite far, column vectors (glm >= 1.0 only).
template <class T>
Mat4 infinitePerspectiveRH_ZO(T fovy, T aspect, T zNear) {
  return toMat4(detail::infinitePerspective<T>(fovy, aspect, zNear, true, true));
}
// NO, LH, infinite far, column vectors (glm 0.9.9's infinitePerspectiveLH).
template <class T>
Mat4 infinitePerspectiveLH_NO(T fovy, T aspect, T zNear) {
  return toMat4(detail::infinitePerspective<T>(fovy, aspect, zNear, false, false));
}
// ZO, LH, infinite far, column vectors (glm >= 1.0 only).
template <class T>
Mat4 infinitePerspectiveLH_ZO(T fovy, T aspect, T zNear) {
  return toMat4(detail::infinitePerspective<T>(fovy, aspect, zNear, false, true));
}

// NO, RH, infinite far with Lengyel's epsilon (z_ndc -> 1 - ep at infinity), column vectors.
// glm::tweakedInfinitePerspective; glm's default ep is epsilon<T>().
template <class T>
Mat4 tweakedInfinitePerspective(T fovy, T aspect, T zNear, T ep) {
  const T range = std::tan(fovy / T(2)) * zNear;
  const T left = -range * aspect;
  const T right = range * aspect;
  const T bottom = -range;
  const T top = range;
  Mat4T<T> m = zeroT<T>();
  el(m, 0, 0) = (T(2) * zNear) / (right - left);
  el(m, 1, 1) = (T(2) * zNear) / (top - bottom);
  el(m, 2, 2) = ep - T(1);
  el(m, 2, 3) = T(-1);
  el(m, 3, 2) = (ep - T(2)) * zNear;
  return toMat4(m);
}

// --- frustum(l, r, b, t, near, far): off-axis window on the near plane, finite far. ---

// NO, RH, finite far, column vectors (glFrustum).
template <class T>
Mat4 frustumRH_NO(T l, T r, T b, T t, T n, T f) {
  return toMat4(detail::frustum<T>(l, r, b, t, n, f, true, false));
}
// ZO, RH, finite far, column vectors.
template <class T>
Mat4 frustumRH_ZO(T l, T r, T b, T t, T n, T f) {
  return toMat4(detail::frustum<T>(l, r, b, t, n, f, true, true));
}
// NO, LH, finite far, column vectors (glm 1.0 sign of [2][0], [2][1]; see the note at the top).
template <class T>
Mat4 frustumLH_NO(T l, T r, T b, T t, T n, T f) {
  return toMat4(detail::frustum<T>(l, r, b, t, n, f, false, false));
}
// ZO, LH, finite far, column vectors (glm 1.0 sign of [2][0], [2][1]).
template <class T>
Mat4 frustumLH_ZO(T l, T r, T b, T t, T n, T f) {
  return toMat4(detail::frustum<T>(l, r, b, t, n, f, false, true));
}

// --- ortho(l, r, b, t, near, far): orthographic (w_clip = 1), finite far. ---

// NO, RH (near/far are distances along -z), column vectors (glOrtho).
template <class T>
Mat4 orthoRH_NO(T l, T r, T b, T t, T zNear, T zFar) {
  return toMat4(detail::ortho<T>(l, r, b, t, zNear, zFar, true, false));
}
// ZO, RH, column vectors.
template <class T>
Mat4 orthoRH_ZO(T l, T r, T b, T t, T zNear, T zFar) {
  return toMat4(detail::ortho<T>(l, r, b, t, zNear, zFar, true, true));
}
// NO, LH (near/far along +z), column vectors.
template <class T>
Mat4 orthoLH_NO(T l, T r, T b, T t, T zNear, T zFar) {
  return toMat4(detail::ortho<T>(l, r, b, t, zNear, zFar, false, false));
}
// ZO, LH, column vectors (XMMatrixOrthographicOffCenterLH).
template <class T>
Mat4 orthoLH_ZO(T l, T r, T b, T t, T zNear, T zFar) {
  return toMat4(detail::ortho<T>(l, r, b, t, zNear, zFar, false, true));
}

// --- view-from-world ---

// RH view (camera looks down -z of its view space, +y up, +x right), column vectors.
template <class T>
Mat4 lookAtRH(Vec3T<T> eye, Vec3T<T> center, Vec3T<T> up) {
  const Vec3T<T> f = detail::normalize(detail::sub(center, eye));
  const Vec3T<T> s = detail::normalize(detail::cross(f, up));
  const Vec3T<T> u = detail::cross(s, f);
  Mat4T<T> m = identityT<T>();
  el(m, 0, 0) = s.x;
  el(m, 1, 0) = s.y;
  el(m, 2, 0) = s.z;
  el(m, 0, 1) = u.x;
  el(m, 1, 1) = u.y;
  el(m, 2, 1) = u.z;
  el(m, 0, 2) = -f.x;
  el(m, 1, 2) = -f.y;
  el(m, 2, 2) = -f.z;
  el(m, 3, 0) = -detail::dot(s, eye);
  el(m, 3, 1) = -detail::dot(u, eye);
  el(m, 3, 2) = detail::dot(f, eye);
  return toMat4(m);
}

// LH view (camera looks down +z of its view space, +y up, +x right), column vectors. In a world
// read as right-handed the image of lookAtLH * perspectiveLH_* is mirrored relative to the RH pair:
// LH conventions assume a left-handed world.
template <class T>
Mat4 lookAtLH(Vec3T<T> eye, Vec3T<T> center, Vec3T<T> up) {
  const Vec3T<T> f = detail::normalize(detail::sub(center, eye));
  const Vec3T<T> s = detail::normalize(detail::cross(up, f));
  const Vec3T<T> u = detail::cross(f, s);
  Mat4T<T> m = identityT<T>();
  el(m, 0, 0) = s.x;
  el(m, 1, 0) = s.y;
  el(m, 2, 0) = s.z;
  el(m, 0, 1) = u.x;
  el(m, 1, 1) = u.y;
  el(m, 2, 1) = u.z;
  el(m, 0, 2) = f.x;
  el(m, 1, 2) = f.y;
  el(m, 2, 2) = f.z;
  el(m, 3, 0) = -detail::dot(s, eye);
  el(m, 3, 1) = -detail::dot(u, eye);
  el(m, 3, 2) = -detail::dot(f, eye);
  return toMat4(m);
}

// proj * view computed in T like glm's mat4 operator* (what an app computing in float uploads).
template <class T>
Mat4 clipFromWorld(const Mat4& proj, const Mat4& view) {
  return toMat4(multiplyT<T>(fromMat4<T>(proj), fromMat4<T>(view)));
}

}  // namespace clipray::testing::engines::glmx

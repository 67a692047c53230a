#pragma once
// Filament's camera, written from google/filament:
//   filament/src/details/Camera.cpp  FCamera::projection (fov / aspect -> frustum, far = inf
//                                    handled), setProjection (PERSPECTIVE: far replaced by
//                                    infinity for rendering, finite for culling; ORTHO),
//                                    getProjectionMatrix ("GL to inverted DX convention")
//   filament/src/details/Camera.h    CameraInfo: projection = mat4f(getProjectionMatrix()),
//                                    view = inverse(model); rigidTransformInverse
//   libs/math/include/math/mat4.h    TMat44::frustum, ortho, lookAt (camera pose looking down -z)
// Filament computes camera matrices in double (math::mat4) and hands the shaders float (mat4f):
// the faithful values are T = double followed by roundToFloat32(). Column-major, column vectors:
// the GL array as is.
//
// The user projection (setProjection, getUserProjectionMatrix) is GL NO, RH, with the far plane
// at infinity. What the shaders receive (CameraInfo::projection, from getProjectionMatrix) is
// M * P with M's third row (0, 0, -0.5, 0.5): reversed ZO, RH, infinite far; for a perspective P
// its third row is exactly (0, 0, 0, near) (z_ndc = near / -z_view: 1 at the near plane, 0 at
// infinity). How the backend then maps z to the depth buffer (clip control, or a remap in the
// vertex shader) is backend code, not modelled here.

#include <cmath>
#include <numbers>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::filament {

enum class Fov { Vertical, Horizontal };

// TMat44<T>::frustum(left, right, bottom, top, near, far). NO, RH, finite far, column vectors.
template <class T>
Mat4T<T> frustumT(T left, T right, T bottom, T top, T near, T far) {
  Mat4T<T> m = identityT<T>();
  el(m, 0, 0) = (T(2) * near) / (right - left);
  el(m, 1, 1) = (T(2) * near) / (top - bottom);
  el(m, 2, 0) = (right + left) / (right - left);
  el(m, 2, 1) = (top + bottom) / (top - bottom);
  el(m, 2, 2) = -(far + near) / (far - near);
  el(m, 2, 3) = T(-1);
  el(m, 3, 2) = -(T(2) * far * near) / (far - near);
  el(m, 3, 3) = T(0);
  return m;
}

// TMat44<T>::ortho(left, right, bottom, top, near, far). NO, RH, column vectors.
template <class T>
Mat4 ortho(T left, T right, T bottom, T top, T near, T far) {
  Mat4T<T> m = identityT<T>();
  el(m, 0, 0) = T(2) / (right - left);
  el(m, 1, 1) = T(2) / (top - bottom);
  el(m, 2, 2) = T(-2) / (far - near);
  el(m, 3, 0) = -(right + left) / (right - left);
  el(m, 3, 1) = -(top + bottom) / (top - bottom);
  el(m, 3, 2) = -(far + near) / (far - near);
  return toMat4(m);
}

// Camera::setProjection(PERSPECTIVE, left, right, bottom, top, near, far) as used for rendering:
// frustum() with p[2][2] = -1, p[3][2] = -2 * near (lim far -> inf). NO, RH, infinite far, column
// vectors (the user projection, before getProjectionMatrix's remap).
template <class T>
Mat4 userPerspective(T left, T right, T bottom, T top, T near, T far) {
  Mat4T<T> p = frustumT<T>(left, right, bottom, top, near, far);
  el(p, 2, 2) = T(-1);
  el(p, 3, 2) = T(-2) * near;
  return toMat4(p);
}

// The culling projection of the same call (Camera::getCullingProjectionMatrix without
// scaling / shift): frustum() with the finite far. NO, RH, finite far, column vectors.
template <class T>
Mat4 cullingPerspective(T left, T right, T bottom, T top, T near, T far) {
  return toMat4(frustumT<T>(left, right, bottom, top, near, far));
}

// FCamera::projection(direction, fovInDegrees, aspect, near, far) -> the window passed to
// setProjection: s = tan(fov * DEG_TO_RAD / 2) * near; vertical: w = s * aspect, h = s;
// horizontal: w = s, h = s / aspect. Camera::setProjection(fov, aspect, near, far, direction)
// renders with userPerspective(-w, w, -h, h, near, far). NO, RH, infinite far, column vectors.
template <class T>
Mat4 userPerspectiveFov(T fovInDegrees, T aspect, T near, T far, Fov direction = Fov::Vertical) {
  const T degToRad = static_cast<T>(std::numbers::pi / 180.0);
  const T s = std::tan(fovInDegrees * degToRad / T(2)) * near;
  const T w = direction == Fov::Vertical ? s * aspect : s;
  const T h = direction == Fov::Vertical ? s : s / aspect;
  return userPerspective<T>(-w, w, -h, h, near, far);
}

// FCamera::getProjectionMatrix(): row_major_init{sx, 0, 0, shiftX; 0, sy, 0, shiftY;
// 0, 0, -0.5, 0.5; 0, 0, 0, 1} * userProjection ("GL to inverted DX convention"). For a
// perspective user projection: reversed ZO, RH, infinite far; for an ortho one: reversed ZO, RH.
// Column vectors. Default scaling (1, 1), shift (0, 0) (Camera::setScaling / setShift).
template <class T>
Mat4 projectionForShaders(const Mat4& userProjection, T scaleX = T(1), T scaleY = T(1),
                          T shiftX = T(0), T shiftY = T(0)) {
  Mat4T<T> m = zeroT<T>();
  el(m, 0, 0) = scaleX;
  el(m, 3, 0) = shiftX;
  el(m, 1, 1) = scaleY;
  el(m, 3, 1) = shiftY;
  el(m, 2, 2) = T(-0.5);
  el(m, 3, 2) = T(0.5);
  el(m, 3, 3) = T(1);
  return toMat4(multiplyT<T>(m, fromMat4<T>(userProjection)));
}

// View matrix of a camera placed with Camera::lookAt(eye, center, up): the model matrix is
// mat4::lookAt (z_axis = normalize(center - eye), x = normalize(cross(z_axis, normalize(up))),
// y = cross(x, z_axis), columns (x, y, -z_axis, eye): the camera looks down -z, RH), and the view
// is its inverse (rigid here; Filament uses a general inverse in double). Column vectors. The
// degenerate-up fix of mat4::lookAt (|dot| > 0.999) is reproduced.
template <class T>
Mat4 viewFromLookAt(Vec3T<T> eye, Vec3T<T> center, Vec3T<T> up) {
  auto dot = [](Vec3T<T> a, Vec3T<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  auto normalize = [&](Vec3T<T> v) {
    const T s = T(1) / std::sqrt(dot(v, v));
    return Vec3T<T>{v.x * s, v.y * s, v.z * s};
  };
  auto cross = [](Vec3T<T> a, Vec3T<T> b) {
    return Vec3T<T>{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  const Vec3T<T> zAxis = normalize(Vec3T<T>{center.x - eye.x, center.y - eye.y, center.z - eye.z});
  Vec3T<T> normUp = normalize(up);
  if (std::abs(dot(zAxis, normUp)) > T(0.999)) normUp = {normUp.z, normUp.x, normUp.y};
  const Vec3T<T> xAxis = normalize(cross(zAxis, normUp));
  const Vec3T<T> yAxis = cross(xAxis, zAxis);
  Mat4T<T> model = identityT<T>();
  el(model, 0, 0) = xAxis.x;
  el(model, 0, 1) = xAxis.y;
  el(model, 0, 2) = xAxis.z;
  el(model, 1, 0) = yAxis.x;
  el(model, 1, 1) = yAxis.y;
  el(model, 1, 2) = yAxis.z;
  el(model, 2, 0) = -zAxis.x;
  el(model, 2, 1) = -zAxis.y;
  el(model, 2, 2) = -zAxis.z;
  el(model, 3, 0) = eye.x;
  el(model, 3, 1) = eye.y;
  el(model, 3, 2) = eye.z;
  return toMat4(rigidInverseT<T>(model));
}

}  // namespace clipray::testing::engines::filament

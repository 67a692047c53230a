#pragma once
// raylib's cameras, written from raysan5/raylib:
//   src/raymath.h  MatrixFrustum, MatrixPerspective, MatrixOrtho, MatrixLookAt; DEG2RAD =
//                  PI / 180.0f with PI a float literal
//   src/rcamera.h  GetCameraProjectionMatrix, GetCameraViewMatrix (CAMERA_CULL_DISTANCE_NEAR /
//                  FAR = RL_CULL_DISTANCE_NEAR / FAR = 0.05 / 4000.0)
//   src/rcore.c    BeginMode3D: top = near * tan(fovy * 0.5 * DEG2RAD), rlFrustum / rlOrtho
//   src/rlgl.h     rlFrustum, rlOrtho (same formulas as MatrixFrustum / MatrixOrtho)
// raylib's Matrix has fields m0..m15 named in column-major order (m0 m1 m2 m3 = column 0) and
// rlgl uploads them in that order (MatrixToFloatV), with column vectors: m_k is element k of the
// GL array. raylib mixes precisions: parameters are double, the matrix entries are computed in
// float. Below, double stays double and raylib's float is T, so T = float is bit-exact.
//
// All projections: NO, RH (camera looks down -z), finite far, not reversed, column vectors.

#include <cmath>
#include <numbers>
#include <type_traits>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::raylib {

inline constexpr double kCullNear = 0.05;   // RL_CULL_DISTANCE_NEAR
inline constexpr double kCullFar = 4000.0;  // RL_CULL_DISTANCE_FAR

// DEG2RAD = (PI/180.0f) with PI the float literal 3.14159265358979323846f; T = double uses the
// double pi (raylib has no double build).
template <class T>
constexpr T deg2rad() {
  if constexpr (std::is_same_v<T, float>)
    return 3.14159265358979323846f / 180.0f;
  else
    return static_cast<T>(std::numbers::pi) / T(180);
}

// MatrixFrustum(left, right, bottom, top, nearPlane, farPlane) (and rlFrustum). NO, RH, finite.
template <class T>
Mat4 matrixFrustum(double left, double right, double bottom, double top, double nearPlane,
                   double farPlane) {
  const T rl = static_cast<T>(right - left);
  const T tb = static_cast<T>(top - bottom);
  const T fn = static_cast<T>(farPlane - nearPlane);
  Mat4T<T> m = zeroT<T>();
  m[0] = (static_cast<T>(nearPlane) * T(2)) / rl;
  m[5] = (static_cast<T>(nearPlane) * T(2)) / tb;
  m[8] = (static_cast<T>(right) + static_cast<T>(left)) / rl;
  m[9] = (static_cast<T>(top) + static_cast<T>(bottom)) / tb;
  m[10] = -(static_cast<T>(farPlane) + static_cast<T>(nearPlane)) / fn;
  m[11] = T(-1);
  m[14] = -(static_cast<T>(farPlane) * static_cast<T>(nearPlane) * T(2)) / fn;
  return toMat4(m);
}

// MatrixPerspective(fovY (radians), aspect, nearPlane, farPlane): the window is computed in
// double, then MatrixFrustum's float formulas. NO, RH, finite far.
template <class T>
Mat4 matrixPerspective(double fovY, double aspect, double nearPlane, double farPlane) {
  const double top = nearPlane * std::tan(fovY * 0.5);
  const double right = top * aspect;
  return matrixFrustum<T>(-right, right, -top, top, nearPlane, farPlane);
}

// MatrixOrtho(left, right, bottom, top, nearPlane, farPlane) (and rlOrtho). NO, RH, w = 1.
template <class T>
Mat4 matrixOrtho(double left, double right, double bottom, double top, double nearPlane,
                 double farPlane) {
  const T rl = static_cast<T>(right - left);
  const T tb = static_cast<T>(top - bottom);
  const T fn = static_cast<T>(farPlane - nearPlane);
  Mat4T<T> m = zeroT<T>();
  m[0] = T(2) / rl;
  m[5] = T(2) / tb;
  m[10] = T(-2) / fn;
  m[12] = -(static_cast<T>(left) + static_cast<T>(right)) / rl;
  m[13] = -(static_cast<T>(top) + static_cast<T>(bottom)) / tb;
  m[14] = -(static_cast<T>(farPlane) + static_cast<T>(nearPlane)) / fn;
  m[15] = T(1);
  return toMat4(m);
}

// MatrixLookAt(eye, target, up) (= GetCameraViewMatrix): vz = normalize(eye - target), vx =
// normalize(up x vz), vy = vz x vx (normalize multiplies by 1 / length, length 0 -> 1). RH (looks
// down -z), column vectors.
template <class T>
Mat4 matrixLookAt(Vec3T<T> eye, Vec3T<T> target, Vec3T<T> up) {
  auto normalize = [](Vec3T<T> v) {
    T length = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    if (length == T(0)) length = T(1);
    const T ilength = T(1) / length;
    return Vec3T<T>{v.x * ilength, v.y * ilength, v.z * ilength};
  };
  auto cross = [](Vec3T<T> a, Vec3T<T> b) {
    return Vec3T<T>{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  const Vec3T<T> vz = normalize({eye.x - target.x, eye.y - target.y, eye.z - target.z});
  const Vec3T<T> vx = normalize(cross(up, vz));
  const Vec3T<T> vy = cross(vz, vx);
  Mat4T<T> m = zeroT<T>();
  m[0] = vx.x;
  m[1] = vy.x;
  m[2] = vz.x;
  m[4] = vx.y;
  m[5] = vy.y;
  m[6] = vz.y;
  m[8] = vx.z;
  m[9] = vy.z;
  m[10] = vz.z;
  m[12] = -(vx.x * eye.x + vx.y * eye.y + vx.z * eye.z);
  m[13] = -(vy.x * eye.x + vy.y * eye.y + vy.z * eye.z);
  m[14] = -(vz.x * eye.x + vz.y * eye.y + vz.z * eye.z);
  m[15] = T(1);
  return toMat4(m);
}

// GetCameraProjectionMatrix(camera, aspect) for CAMERA_PERSPECTIVE: MatrixPerspective(fovy *
// DEG2RAD (float product), aspect, 0.05, 4000). fovy in degrees. NO, RH, finite far.
template <class T>
Mat4 cameraPerspective(T fovyDegrees, T aspect) {
  return matrixPerspective<T>(static_cast<double>(fovyDegrees * deg2rad<T>()),
                              static_cast<double>(aspect), kCullNear, kCullFar);
}

// GetCameraProjectionMatrix for CAMERA_ORTHOGRAPHIC: fovy is the view height. NO, RH, w = 1.
template <class T>
Mat4 cameraOrthographic(T fovy, T aspect) {
  const double top = static_cast<double>(fovy) / 2.0;
  const double right = top * static_cast<double>(aspect);
  return matrixOrtho<T>(-right, right, -top, top, kCullNear, kCullFar);
}

// BeginMode3D(camera) for CAMERA_PERSPECTIVE on a width x height framebuffer: aspect =
// (float)width / (float)height, top = near * tan(fovy * 0.5 * DEG2RAD) in double, rlFrustum. NO,
// RH, finite far (differs from cameraPerspective in the last bits of [0][0], [1][1]).
template <class T>
Mat4 beginMode3DPerspective(T fovyDegrees, int width, int height) {
  const T aspect = static_cast<T>(width) / static_cast<T>(height);
  const double top = kCullNear * std::tan(static_cast<double>(fovyDegrees) * 0.5 *
                                          static_cast<double>(deg2rad<T>()));
  const double right = top * static_cast<double>(aspect);
  return matrixFrustum<T>(-right, right, -top, top, kCullNear, kCullFar);
}

}  // namespace clipray::testing::engines::raylib

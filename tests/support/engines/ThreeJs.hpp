#pragma once
// three.js cameras, written from mrdoob/three.js:
//   src/math/Matrix4.js                 makePerspective / makeOrthographic (coordinateSystem,
//                                       reversedDepth), lookAt, elements column-major
//   src/cameras/PerspectiveCamera.js    updateProjectionMatrix (fov, aspect, zoom, view offset,
//                                       filmOffset)
//   src/cameras/OrthographicCamera.js   updateProjectionMatrix (zoom around the centre)
//   src/constants.js                    WebGLCoordinateSystem = 2000, WebGPUCoordinateSystem = 2001
//   src/math/MathUtils.js               DEG2RAD = Math.PI / 180
// Matrix4.elements is column-major and three.js uses column vectors, so the result is the GL array
// as is. JavaScript computes in double and WebGL uploads a Float32Array: the faithful values are
// T = double followed by roundToFloat32(); T = float models a float32 port.
//
// Depth: WebGLCoordinateSystem -> NO; WebGPUCoordinateSystem -> ZO (WebGPU NDC is y-up like GL;
// its framebuffer y-down is handled by the viewport, so no y flip in the matrix). reversedDepth
// (recent releases, whose Matrix4 methods take the argument; camera.reversedDepth follows the
// renderer's reversed depth buffer) gives reversed ZO, near -> 1, far -> 0, for both coordinate
// systems (on WebGL through EXT_clip_control). View space is RH (camera looks down -z). No
// infinite far: makePerspective(far = Infinity) gives NaN.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::threejs {

enum class CoordinateSystem { WebGL = 2000, WebGPU = 2001 };

// Matrix4.makePerspective(left, right, top, bottom, near, far, coordinateSystem, reversedDepth).
// Note the argument order: top before bottom. RH, finite far, column vectors; NO (WebGL), ZO
// (WebGPU) or reversed ZO (reversedDepth, either system).
template <class T>
Mat4 makePerspective(T left, T right, T top, T bottom, T near, T far,
                     CoordinateSystem cs = CoordinateSystem::WebGL, bool reversedDepth = false) {
  const T x = T(2) * near / (right - left);
  const T y = T(2) * near / (top - bottom);
  const T a = (right + left) / (right - left);
  const T b = (top + bottom) / (top - bottom);
  T c, d;
  if (reversedDepth) {
    c = near / (far - near);
    d = (far * near) / (far - near);
  } else if (cs == CoordinateSystem::WebGL) {
    c = -(far + near) / (far - near);
    d = (T(-2) * far * near) / (far - near);
  } else {
    c = -far / (far - near);
    d = (-far * near) / (far - near);
  }
  Mat4T<T> te = zeroT<T>();
  te[0] = x;
  te[8] = a;
  te[5] = y;
  te[9] = b;
  te[10] = c;
  te[14] = d;
  te[11] = T(-1);
  return toMat4(te);
}

// Matrix4.makeOrthographic(left, right, top, bottom, near, far, coordinateSystem, reversedDepth).
// RH, column vectors, w = 1; NO (WebGL), ZO (WebGPU) or reversed ZO (reversedDepth).
template <class T>
Mat4 makeOrthographic(T left, T right, T top, T bottom, T near, T far,
                      CoordinateSystem cs = CoordinateSystem::WebGL, bool reversedDepth = false) {
  const T x = T(2) / (right - left);
  const T y = T(2) / (top - bottom);
  const T a = -(right + left) / (right - left);
  const T b = -(top + bottom) / (top - bottom);
  T c, d;
  if (reversedDepth) {
    c = T(1) / (far - near);
    d = far / (far - near);
  } else if (cs == CoordinateSystem::WebGL) {
    c = T(-2) / (far - near);
    d = -(far + near) / (far - near);
  } else {
    c = T(-1) / (far - near);
    d = -near / (far - near);
  }
  Mat4T<T> te = zeroT<T>();
  te[0] = x;
  te[12] = a;
  te[5] = y;
  te[13] = b;
  te[10] = c;
  te[14] = d;
  te[15] = T(1);
  return toMat4(te);
}

// PerspectiveCamera.setViewOffset(fullWidth, fullHeight, x, y, width, height) state.
template <class T>
struct ViewOffset {
  T fullWidth, fullHeight, offsetX, offsetY, width, height;
};

// PerspectiveCamera(fov in degrees, aspect, near, far) after updateProjectionMatrix(), with zoom,
// optional view offset and filmOffset (filmGauge 35 by default). RH, finite far, column vectors;
// depth as makePerspective. Off-axis when a view offset or filmOffset is set.
template <class T>
Mat4 perspectiveCamera(T fov, T aspect, T near, T far,
                       CoordinateSystem cs = CoordinateSystem::WebGL, bool reversedDepth = false,
                       T zoom = T(1), const ViewOffset<T>* view = nullptr, T filmOffset = T(0),
                       T filmGauge = T(35)) {
  const T deg2rad = static_cast<T>(std::numbers::pi / 180.0);
  T top = near * std::tan(deg2rad * T(0.5) * fov) / zoom;
  T height = T(2) * top;
  T width = aspect * height;
  T left = T(-0.5) * width;
  if (view != nullptr) {
    left += view->offsetX * width / view->fullWidth;
    top -= view->offsetY * height / view->fullHeight;
    width *= view->width / view->fullWidth;
    height *= view->height / view->fullHeight;
  }
  if (filmOffset != T(0)) left += near * filmOffset / (filmGauge * std::min(aspect, T(1)));
  return makePerspective<T>(left, left + width, top, top - height, near, far, cs, reversedDepth);
}

// OrthographicCamera(left, right, top, bottom, near, far) after updateProjectionMatrix() with zoom
// (no view offset). RH, column vectors; depth as makeOrthographic.
template <class T>
Mat4 orthographicCamera(T left, T right, T top, T bottom, T near, T far,
                        CoordinateSystem cs = CoordinateSystem::WebGL, bool reversedDepth = false,
                        T zoom = T(1)) {
  const T dx = (right - left) / (T(2) * zoom);
  const T dy = (top - bottom) / (T(2) * zoom);
  const T cx = (right + left) / T(2);
  const T cy = (top + bottom) / T(2);
  return makeOrthographic<T>(cx - dx, cx + dx, cy + dy, cy - dy, near, far, cs, reversedDepth);
}

// camera.matrixWorldInverse of a camera at eye after camera.lookAt(target) with camera.up = up.
// Object3D.lookAt uses Matrix4.lookAt(eye, target, up) for cameras: z = normalize(eye - target),
// x = normalize(cross(up, z)), y = cross(z, x) (the camera looks down -z: RH). three.js then goes
// through a quaternion, compose() and invert(); this rigid inverse of the lookAt basis equals it up
// to the last bits. Column vectors. (The degenerate up || z nudge of Matrix4.lookAt is not
// reproduced.)
template <class T>
Mat4 viewFromLookAt(Vec3T<T> eye, Vec3T<T> target, Vec3T<T> up) {
  auto normalize = [](Vec3T<T> v) {
    T len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    if (len == T(0)) len = T(1);  // Vector3.normalize: divideScalar(length() || 1)
    const T s = T(1) / len;       // divideScalar = multiplyScalar(1 / scalar)
    return Vec3T<T>{v.x * s, v.y * s, v.z * s};
  };
  auto cross = [](Vec3T<T> a, Vec3T<T> b) {
    return Vec3T<T>{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  Vec3T<T> z{eye.x - target.x, eye.y - target.y, eye.z - target.z};
  if (z.x * z.x + z.y * z.y + z.z * z.z == T(0)) z.z = T(1);
  z = normalize(z);
  const Vec3T<T> x = normalize(cross(up, z));
  const Vec3T<T> y = cross(z, x);
  Mat4T<T> world = identityT<T>();
  world[0] = x.x;
  world[4] = y.x;
  world[8] = z.x;
  world[1] = x.y;
  world[5] = y.y;
  world[9] = z.y;
  world[2] = x.z;
  world[6] = y.z;
  world[10] = z.z;
  world[12] = eye.x;
  world[13] = eye.y;
  world[14] = eye.z;
  return toMat4(rigidInverseT<T>(world));
}

}  // namespace clipray::testing::engines::threejs

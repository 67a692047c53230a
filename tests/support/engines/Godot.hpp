#pragma once
// Godot 4 cameras, written from godotengine/godot:
//   core/math/projection.cpp (core/math/projection.h in recent versions, where the same bodies
//     are inline): set_perspective, get_fovy, set_frustum, set_orthogonal, set_depth_correction,
//     add_jitter_offset, operator*
//   core/math/basis.cpp        Basis::looking_at;  core/math/vector3.h  normalize, cross
//   servers/rendering/renderer_rd/storage_rd/render_scene_data_rd.cpp  RD (Vulkan / D3D12 /
//     Metal) camera: correction.set_depth_correction(flip_y); add_jitter_offset(taa_jitter);
//     correction * cam_projection
//   drivers/gles3/rasterizer_scene_gles3.cpp  Compatibility (OpenGL) renderer:
//     correction.set_depth_correction(p_flip_y, true, false); correction * cam_projection
// Projection stores four column Vector4s (columns[col][row]) and uses column vectors; shaders get
// it through MaterialStorage::store_camera, which writes columns[i][j] at 4 * i + j: the GL array
// as is. real_t is float unless Godot is built with precision=double; some expressions mix in
// double literals (2.0 / x, deg_to_rad(x / 2.0)) and are evaluated in double, as below.
//
// Camera3D's projection (set_perspective / set_frustum / set_orthogonal) is the plain GL one: NO,
// RH (looks down -z), finite far. Since Godot 4.3 the renderers reverse Z afterwards with the
// depth-correction matrix: RD -> reversed ZO (+ optional y flip, TAA jitter); Compatibility ->
// reversed NO (z_ndc: near +1, far -1). Godot 4.0-4.2 used set_depth_correction(flip_y) = remap to
// [0, 1] without reversal.

#include <cmath>
#include <numbers>
#include <type_traits>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::godot {

namespace detail {

// Math::deg_to_rad: the float overload multiplies by (float)(Math_PI / 180.0), the double one by
// (Math_PI / 180.0).
template <class T>
T degToRad(T deg) {
  if constexpr (std::is_same_v<T, float>)
    return deg * static_cast<float>(std::numbers::pi / 180.0);
  else
    return deg * (std::numbers::pi / 180.0);
}

}  // namespace detail

// Projection::get_fovy(fovx, aspect): the vertical fov (degrees) of a horizontal fov.
template <class T>
T getFovy(T fovx, T aspect) {
  const double half = static_cast<double>(detail::degToRad<T>(fovx)) * 0.5;
  const double r = std::atan(static_cast<double>(aspect) * std::tan(half)) * 2.0;
  return static_cast<T>(r * (180.0 / std::numbers::pi));
}

// Projection::set_perspective(fovy_degrees, aspect, z_near, z_far, flip_fov). With flip_fov the
// fov is horizontal (Camera3D KEEP_WIDTH). NO, RH, finite far, column vectors.
template <class T>
Mat4 setPerspective(T fovyDegrees, T aspect, T zNear, T zFar, bool flipFov = false) {
  if (flipFov)
    fovyDegrees = getFovy<T>(fovyDegrees, static_cast<T>(1.0 / static_cast<double>(aspect)));
  const T radians = static_cast<T>(static_cast<double>(fovyDegrees) / 2.0 *
                                   (std::numbers::pi / 180.0));  // deg_to_rad(double)
  const T deltaZ = zFar - zNear;
  const T sine = std::sin(radians);
  const T cotangent = std::cos(radians) / sine;
  Mat4T<T> m = identityT<T>();
  el(m, 0, 0) = cotangent / aspect;
  el(m, 1, 1) = cotangent;
  el(m, 2, 2) = -(zFar + zNear) / deltaZ;
  el(m, 2, 3) = T(-1);
  el(m, 3, 2) = T(-2) * zNear * zFar / deltaZ;
  el(m, 3, 3) = T(0);
  return toMat4(m);
}

// Projection::set_frustum(left, right, bottom, top, near, far). NO, RH, finite far, column
// vectors; off-axis when left != -right or bottom != -top.
template <class T>
Mat4 setFrustum(T left, T right, T bottom, T top, T near, T far) {
  const T x = T(2) * near / (right - left);
  const T y = T(2) * near / (top - bottom);
  const T a = (right + left) / (right - left);
  const T b = (top + bottom) / (top - bottom);
  const T c = -(far + near) / (far - near);
  const T d = T(-2) * far * near / (far - near);
  Mat4T<T> te = zeroT<T>();
  te[0] = x;
  te[5] = y;
  te[8] = a;
  te[9] = b;
  te[10] = c;
  te[11] = T(-1);
  te[14] = d;
  return toMat4(te);
}

// Projection::set_frustum(size, aspect, offset, near, far, flip_fov): Camera3D's PROJECTION_FRUSTUM
// (size = frustum height on the near plane, or width with KEEP_WIDTH). NO, RH, finite far.
template <class T>
Mat4 setFrustumAspect(T size, T aspect, T offsetX, T offsetY, T near, T far, bool flipFov = false) {
  if (!flipFov) size *= aspect;
  return setFrustum<T>(-size / T(2) + offsetX, +size / T(2) + offsetX,
                       -size / aspect / T(2) + offsetY, +size / aspect / T(2) + offsetY, near, far);
}

// Projection::set_orthogonal(left, right, bottom, top, znear, zfar). NO, RH, column vectors.
template <class T>
Mat4 setOrthogonal(T left, T right, T bottom, T top, T zNear, T zFar) {
  Mat4T<T> m = identityT<T>();
  el(m, 0, 0) = static_cast<T>(2.0 / static_cast<double>(right - left));
  el(m, 3, 0) = -((right + left) / (right - left));
  el(m, 1, 1) = static_cast<T>(2.0 / static_cast<double>(top - bottom));
  el(m, 3, 1) = -((top + bottom) / (top - bottom));
  el(m, 2, 2) = static_cast<T>(-2.0 / static_cast<double>(zFar - zNear));
  el(m, 3, 2) = -((zFar + zNear) / (zFar - zNear));
  el(m, 3, 3) = T(1);
  return toMat4(m);
}

// Projection::set_orthogonal(size, aspect, znear, zfar, flip_fov): Camera3D's PROJECTION_ORTHOGONAL
// (size = view height, or width with KEEP_WIDTH). NO, RH, column vectors.
template <class T>
Mat4 setOrthogonalAspect(T size, T aspect, T zNear, T zFar, bool flipFov = false) {
  if (!flipFov) size *= aspect;
  return setOrthogonal<T>(-size / T(2), +size / T(2), -size / aspect / T(2), +size / aspect / T(2),
                          zNear, zFar);
}

// Projection::set_depth_correction(flip_y, reverse_z, remap_z) (defaults true, true, true since
// Godot 4.3): x' = x, y' = flip_y ? -y : y, z' = remap ? (reverse ? -z/2 + w/2 : z/2 + w/2)
// : (reverse ? -z : z). Applied on the left of a NO projection: remap -> ZO, reverse -> reversed.
template <class T>
Mat4 depthCorrection(bool flipY = true, bool reverseZ = true, bool remapZ = true) {
  Mat4T<T> m = zeroT<T>();
  m[0] = T(1);
  m[5] = flipY ? T(-1) : T(1);
  m[10] = remapZ ? (reverseZ ? T(-0.5) : T(0.5)) : (reverseZ ? T(-1) : T(1));
  m[14] = remapZ ? T(0.5) : T(0);
  m[15] = T(1);
  return toMat4(m);
}

// Projection::add_jitter_offset: columns[3][0] += x; columns[3][1] += y (on the correction matrix,
// this shifts clip x, y by jitter * w).
template <class T>
Mat4 addJitterOffset(const Mat4& m, T jitterX, T jitterY) {
  Mat4T<T> out = fromMat4<T>(m);
  el(out, 3, 0) += jitterX;
  el(out, 3, 1) += jitterY;
  return toMat4(out);
}

// The clip-from-view matrix Godot's RD renderers (Forward+, Mobile: Vulkan, D3D12, Metal) upload,
// Godot 4.3+: set_depth_correction(flip_y) (reverse and remap) with TAA jitter, times the
// Camera3D projection. Reversed ZO (near -> 1, far -> 0), RH, y flipped when flipY (Vulkan's
// y-down clip space; Godot sets it when rendering to the screen), column vectors.
template <class T>
Mat4 rdClipFromView(const Mat4& cameraProjection, bool flipY = true, T jitterX = T(0),
                    T jitterY = T(0)) {
  const Mat4 correction =
      addJitterOffset<T>(depthCorrection<T>(flipY, true, true), jitterX, jitterY);
  return toMat4(multiplyT<T>(fromMat4<T>(correction), fromMat4<T>(cameraProjection)));
}

// The clip-from-view matrix of Godot's Compatibility (OpenGL ES 3 / GL 3.3) renderer, 4.3+:
// set_depth_correction(flip_y, true, false) times the projection. Reversed NO (z_ndc: near +1,
// far -1, so depth near 1, far 0 with the default glDepthRange), RH, column vectors.
template <class T>
Mat4 glesClipFromView(const Mat4& cameraProjection, bool flipY = false) {
  const Mat4 correction = depthCorrection<T>(flipY, true, false);
  return toMat4(multiplyT<T>(fromMat4<T>(correction), fromMat4<T>(cameraProjection)));
}

// View-from-world of a Camera3D at eye after look_at(target, up): Basis::looking_at(target - eye,
// up) gives columns x = normalize(up x z), y = z x x, z = -normalize(target - eye) (the camera
// looks down -z: RH); the view matrix is the transform's affine_inverse() (Godot inverts the basis
// by cofactors; the rigid inverse here equals it up to the last bits). Column vectors.
template <class T>
Mat4 viewLookingAt(Vec3T<T> eye, Vec3T<T> target, Vec3T<T> up) {
  auto normalized = [](Vec3T<T> v) {  // Vector3::normalize: divide by sqrt(length_squared)
    const T lengthsq = v.x * v.x + v.y * v.y + v.z * v.z;
    if (lengthsq == T(0)) return Vec3T<T>{};
    const T length = std::sqrt(lengthsq);
    return Vec3T<T>{v.x / length, v.y / length, v.z / length};
  };
  auto cross = [](Vec3T<T> a, Vec3T<T> b) {  // Vector3::cross
    return Vec3T<T>{(a.y * b.z) - (a.z * b.y), (a.z * b.x) - (a.x * b.z),
                    (a.x * b.y) - (a.y * b.x)};
  };
  Vec3T<T> vz = normalized(Vec3T<T>{target.x - eye.x, target.y - eye.y, target.z - eye.z});
  vz = {-vz.x, -vz.y, -vz.z};
  const Vec3T<T> vx = normalized(cross(up, vz));
  const Vec3T<T> vy = cross(vz, vx);
  Mat4T<T> world = identityT<T>();
  el(world, 0, 0) = vx.x;
  el(world, 0, 1) = vx.y;
  el(world, 0, 2) = vx.z;
  el(world, 1, 0) = vy.x;
  el(world, 1, 1) = vy.y;
  el(world, 1, 2) = vy.z;
  el(world, 2, 0) = vz.x;
  el(world, 2, 1) = vz.y;
  el(world, 2, 2) = vz.z;
  el(world, 3, 0) = eye.x;
  el(world, 3, 1) = eye.y;
  el(world, 3, 2) = eye.z;
  return toMat4(rigidInverseT<T>(world));
}

}  // namespace clipray::testing::engines::godot

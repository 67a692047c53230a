#pragma once
// Common types for the engine camera formulas of tests/support/engines/ (issue #24).
//
// Every builder returns a Mat4: 16 doubles, column-major, element 4 * column + row (the order of
// glm::value_ptr and of a GL mat4 uniform uploaded with transpose = GL_FALSE), p_clip = M * p with
// p a column vector, in GL clip convention (x, y, z, w; NDC = xyz / w, +y up in NDC). Where an
// engine targets [0, 1] depth (ZO) the matrix is still written in this layout; only the z row
// differs.
//
// The builders are templates on the scalar type T the engine computes in (float or double): the
// arithmetic is done in T, in the operation order of the engine's source as far as practical, so a
// T = float build gives the float32 values an app uploads; the result is widened exactly to double.
// Engines that compute in double and upload float32 (three.js, Filament) are reproduced with
// T = double followed by roundToFloat32().

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>

namespace clipray::testing::engines {

using Mat4 = std::array<double, 16>;

template <class T>
using Mat4T = std::array<T, 16>;

template <class T>
struct Vec3T {
  T x{}, y{}, z{};
};
using Vec3 = Vec3T<double>;

// A homogeneous point (x, y, z, w) or a plane (a, b, c, d): a x + b y + c z + d w = 0.
using Vec4 = std::array<double, 4>;

enum class Handedness { Left, Right };

// NO: z_ndc in [-1, 1] (OpenGL default). ZO: z_ndc in [0, 1] (D3D, Vulkan, Metal, WebGPU, or GL
// with glClipControl(..., GL_ZERO_TO_ONE)).
enum class DepthRange { NegOneToOne, ZeroToOne };

// m[col][row] in glm / Godot / Filament notation.
template <class T>
constexpr T& el(Mat4T<T>& m, int col, int row) {
  return m[static_cast<std::size_t>(4 * col + row)];
}
template <class T>
constexpr T el(const Mat4T<T>& m, int col, int row) {
  return m[static_cast<std::size_t>(4 * col + row)];
}

template <class T>
constexpr Mat4T<T> zeroT() {
  Mat4T<T> m{};
  m.fill(T(0));
  return m;
}

template <class T>
constexpr Mat4T<T> identityT() {
  Mat4T<T> m = zeroT<T>();
  m[0] = m[5] = m[10] = m[15] = T(1);
  return m;
}

inline constexpr Mat4 identity() {
  return identityT<double>();
}

// Exact widening of a T matrix to the common double matrix.
template <class T>
constexpr Mat4 toMat4(const Mat4T<T>& m) {
  Mat4 out{};
  for (std::size_t i = 0; i < 16; ++i) out[i] = static_cast<double>(m[i]);
  return out;
}

// Narrowing of the common matrix to T (exact when the values came from a T build).
template <class T>
constexpr Mat4T<T> fromMat4(const Mat4& m) {
  Mat4T<T> out{};
  for (std::size_t i = 0; i < 16; ++i) out[i] = static_cast<T>(m[i]);
  return out;
}

// What a float32 upload (glUniformMatrix4fv, Float32Array, mat4f) keeps of a double matrix.
inline Mat4 roundToFloat32(const Mat4& m) {
  return toMat4(fromMat4<float>(m));
}

inline constexpr Mat4 transpose(const Mat4& m) {
  Mat4 t{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) t[static_cast<std::size_t>(4 * r + c)] = el(m, c, r);
  return t;
}

// a * b in T, with glm's operation order (detail/type_mat4x4.inl operator*): column j of the
// result is ((a[0] * b[j][0] + a[1] * b[j][1]) + a[2] * b[j][2]) + a[3] * b[j][3]. Godot's
// Projection::operator* and Filament's TMat44 product sum in the same order.
template <class T>
constexpr Mat4T<T> multiplyT(const Mat4T<T>& a, const Mat4T<T>& b) {
  Mat4T<T> out{};
  for (int j = 0; j < 4; ++j)
    for (int r = 0; r < 4; ++r)
      el(out, j, r) = el(a, 0, r) * el(b, j, 0) + el(a, 1, r) * el(b, j, 1) +
                      el(a, 2, r) * el(b, j, 2) + el(a, 3, r) * el(b, j, 3);
  return out;
}

inline constexpr Mat4 multiply(const Mat4& a, const Mat4& b) {
  return multiplyT<double>(a, b);
}

// M * p for a homogeneous column vector p.
inline constexpr Vec4 transform(const Mat4& m, const Vec4& p) {
  Vec4 out{};
  for (int r = 0; r < 4; ++r)
    out[static_cast<std::size_t>(r)] =
        el(m, 0, r) * p[0] + el(m, 1, r) * p[1] + el(m, 2, r) * p[2] + el(m, 3, r) * p[3];
  return out;
}

// NDC of a point (w = 1).
inline Vec3 toNdc(const Mat4& m, const Vec3& p) {
  const Vec4 c = transform(m, {p.x, p.y, p.z, 1.0});
  return {c[0] / c[3], c[1] / c[3], c[2] / c[3]};
}

// Vulkan-style y flip: negate clip y (row 1 of any clip-from-X matrix); for a plain projection
// this is proj[1][1] *= -1, what Vulkan apps do with glm (and Godot's set_depth_correction(true)).
inline constexpr Mat4 vulkanYFlip(const Mat4& m) {
  Mat4 out = m;
  for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(4 * c + 1)] = -el(m, c, 1);
  return out;
}

// General inverse by Gauss-Jordan elimination with partial pivoting, in double; nullopt when the
// matrix is singular. Used only by helpers (oblique planes, checks), never by an engine formula.
inline std::optional<Mat4> inverse(const Mat4& m) {
  double a[4][8] = {};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) a[r][c] = el(m, c, r);
    a[r][4 + r] = 1.0;
  }
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    if (a[pivot][c] == 0.0 || !std::isfinite(a[pivot][c])) return std::nullopt;
    if (pivot != c)
      for (int k = 0; k < 8; ++k) std::swap(a[c][k], a[pivot][k]);
    const double inv = 1.0 / a[c][c];
    for (int k = 0; k < 8; ++k) a[c][k] *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == c || a[r][c] == 0.0) continue;
      const double f = a[r][c];
      for (int k = 0; k < 8; ++k) a[r][k] -= f * a[c][k];
    }
  }
  Mat4 out{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(4 * c + r)] = a[r][4 + c];
  return out;
}

// Rigid inverse [R t; 0 1]^-1 = [R^T -R^T t; 0 1] in T: the view-from-world matrix of a camera
// whose world-from-camera (model) matrix is m. Engines that keep a camera pose (three.js, Godot,
// Filament) invert it with a general inverse; this gives the same matrix up to the last bits.
template <class T>
constexpr Mat4T<T> rigidInverseT(const Mat4T<T>& m) {
  Mat4T<T> out = identityT<T>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) el(out, c, r) = el(m, r, c);
  for (int r = 0; r < 3; ++r)
    el(out, 3, r) =
        -(el(m, r, 0) * el(m, 3, 0) + el(m, r, 1) * el(m, 3, 1) + el(m, r, 2) * el(m, 3, 2));
  return out;
}

}  // namespace clipray::testing::engines

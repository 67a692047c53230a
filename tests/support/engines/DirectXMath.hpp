#pragma once
// DirectXMath cameras, written from microsoft/DirectXMath:
//   Inc/DirectXMathMatrix.inl  XMMatrixPerspectiveFovLH / RH, XMMatrixOrthographicLH / RH,
//                              XMMatrixLookAtLH / RH (via XMMatrixLookToLH), XMMatrixMultiply
//   Inc/DirectXMathMisc.inl    XMScalarSinCos (11- / 10-degree minimax polynomials)
//   Inc/DirectXMathVector.inl  XMVector3Normalize (SSE: V / sqrt(dot)), XMVector3Dot, Cross
//   Inc/DirectXMath.h          XM_PI = 3.141592654f, XMConvertToRadians = deg * (XM_PI / 180)
// DirectXMath uses ROW vectors: p_clip = p_row * M, with M.r[0..3] its rows and M.m[i][j] at
// memory float 4 * i + j. Clip space is D3D's: ZO depth (z_ndc in [0, 1]), y up in NDC (the
// viewport flips to y-down pixels), so apart from depth it is the GL clip space. Not reversed
// unless the app swaps NearZ and FarZ (then reversed ZO); no infinite-far variant.
//
// Memory order: the mathematically equivalent column-vector matrix is G = M^T, and G in GL
// column-major order (element 4 * col + row = G(row, col) = M(col, row)) is exactly M's memory
// order. So an XMMATRIX memcpy'd as is reads right as a GL mat4; only an app that uploads
// XMMatrixTranspose(M) (Microsoft's samples do, for HLSL's default column_major packing with
// mul(v, M)) gives a buffer whose GL reading is transposed.
//
// T = float reproduces the x64 (SSE2) code path bit for bit, including XMScalarSinCos; T = double
// uses the same formulas with std::sin / std::cos (DirectXMath itself is float only).

#include <cmath>
#include <numbers>
#include <type_traits>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::dxmath {

// 16 scalars in XMMATRIX memory order: m[i][j] (row i of the row-vector matrix) at 4 * i + j.
template <class T>
using XmMatrix = std::array<T, 16>;

template <class T>
constexpr T& xm(XmMatrix<T>& m, int i, int j) {
  return m[static_cast<std::size_t>(4 * i + j)];
}
template <class T>
constexpr T xm(const XmMatrix<T>& m, int i, int j) {
  return m[static_cast<std::size_t>(4 * i + j)];
}

inline constexpr float XM_PI = 3.141592654f;
inline constexpr float XM_2PI = 6.283185307f;
inline constexpr float XM_1DIV2PI = 0.159154943f;
inline constexpr float XM_PIDIV2 = 1.570796327f;

// XMConvertToRadians: degrees * (XM_PI / 180.0f); T = double uses the double pi.
template <class T>
constexpr T convertToRadians(T degrees) {
  if constexpr (std::is_same_v<T, float>)
    return degrees * (XM_PI / 180.0f);
  else
    return degrees * (static_cast<T>(std::numbers::pi) / T(180));
}

// XMScalarSinCos for float; std::sin / std::cos for double.
template <class T>
void scalarSinCos(T* pSin, T* pCos, T value) {
  if constexpr (!std::is_same_v<T, float>) {
    *pSin = std::sin(value);
    *pCos = std::cos(value);
  } else {
    float quotient = XM_1DIV2PI * value;
    if (value >= 0.0f)
      quotient = static_cast<float>(static_cast<int>(quotient + 0.5f));
    else
      quotient = static_cast<float>(static_cast<int>(quotient - 0.5f));
    float y = value - XM_2PI * quotient;
    float sign;
    if (y > XM_PIDIV2) {
      y = XM_PI - y;
      sign = -1.0f;
    } else if (y < -XM_PIDIV2) {
      y = -XM_PI - y;
      sign = -1.0f;
    } else {
      sign = +1.0f;
    }
    const float y2 = y * y;
    *pSin =
        (((((-2.3889859e-08f * y2 + 2.7525562e-06f) * y2 - 0.00019840874f) * y2 + 0.0083333310f) *
              y2 -
          0.16666667f) *
             y2 +
         1.0f) *
        y;
    const float p =
        ((((-2.6051615e-07f * y2 + 2.4760495e-05f) * y2 - 0.0013888378f) * y2 + 0.041666638f) * y2 -
         0.5f) *
            y2 +
        1.0f;
    *pCos = sign * p;
  }
}

// XMMatrixPerspectiveFovLH(FovAngleY (radians), AspectRatio, NearZ, FarZ). ZO, LH (view looks
// down +z, w = +z), finite far (reversed ZO if NearZ > FarZ), ROW vectors, XMMATRIX memory order.
template <class T>
XmMatrix<T> perspectiveFovLH(T fovAngleY, T aspectRatio, T nearZ, T farZ) {
  T sinFov, cosFov;
  scalarSinCos<T>(&sinFov, &cosFov, T(0.5) * fovAngleY);
  const T height = cosFov / sinFov;
  const T width = height / aspectRatio;
  const T fRange = farZ / (farZ - nearZ);
  XmMatrix<T> m = zeroT<T>();
  xm(m, 0, 0) = width;
  xm(m, 1, 1) = height;
  xm(m, 2, 2) = fRange;
  xm(m, 2, 3) = T(1);
  xm(m, 3, 2) = -fRange * nearZ;
  return m;
}

// XMMatrixPerspectiveFovRH. ZO, RH (looks down -z, w = -z), finite far, ROW vectors, memory order.
template <class T>
XmMatrix<T> perspectiveFovRH(T fovAngleY, T aspectRatio, T nearZ, T farZ) {
  T sinFov, cosFov;
  scalarSinCos<T>(&sinFov, &cosFov, T(0.5) * fovAngleY);
  const T height = cosFov / sinFov;
  const T width = height / aspectRatio;
  const T fRange = farZ / (nearZ - farZ);
  XmMatrix<T> m = zeroT<T>();
  xm(m, 0, 0) = width;
  xm(m, 1, 1) = height;
  xm(m, 2, 2) = fRange;
  xm(m, 2, 3) = T(-1);
  xm(m, 3, 2) = fRange * nearZ;
  return m;
}

// XMMatrixOrthographicLH(ViewWidth, ViewHeight, NearZ, FarZ). ZO, LH, w = 1, ROW vectors.
template <class T>
XmMatrix<T> orthographicLH(T viewWidth, T viewHeight, T nearZ, T farZ) {
  const T fRange = T(1) / (farZ - nearZ);
  XmMatrix<T> m = zeroT<T>();
  xm(m, 0, 0) = T(2) / viewWidth;
  xm(m, 1, 1) = T(2) / viewHeight;
  xm(m, 2, 2) = fRange;
  xm(m, 3, 2) = -fRange * nearZ;
  xm(m, 3, 3) = T(1);
  return m;
}

// XMMatrixOrthographicRH. ZO, RH, w = 1, ROW vectors.
template <class T>
XmMatrix<T> orthographicRH(T viewWidth, T viewHeight, T nearZ, T farZ) {
  const T fRange = T(1) / (nearZ - farZ);
  XmMatrix<T> m = zeroT<T>();
  xm(m, 0, 0) = T(2) / viewWidth;
  xm(m, 1, 1) = T(2) / viewHeight;
  xm(m, 2, 2) = fRange;
  xm(m, 3, 2) = fRange * nearZ;
  xm(m, 3, 3) = T(1);
  return m;
}

// XMMatrixLookToLH(EyePosition, EyeDirection, UpDirection): rows R0 = normalize(up x R2),
// R1 = R2 x R0, R2 = normalize(dir), D_k = dot(R_k, -eye), then transposed. LH (view looks down
// +z), ROW vectors, memory order.
template <class T>
XmMatrix<T> lookToLH(Vec3T<T> eye, Vec3T<T> dir, Vec3T<T> up) {
  auto dot = [](Vec3T<T> a, Vec3T<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  auto cross = [](Vec3T<T> a, Vec3T<T> b) {
    return Vec3T<T>{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  auto normalize = [&](Vec3T<T> v) {  // SSE path: V / sqrt(dot(V, V))
    const T len = std::sqrt(dot(v, v));
    return Vec3T<T>{v.x / len, v.y / len, v.z / len};
  };
  const Vec3T<T> r2 = normalize(dir);
  const Vec3T<T> r0 = normalize(cross(up, r2));
  const Vec3T<T> r1 = cross(r2, r0);
  const Vec3T<T> negEye{-eye.x, -eye.y, -eye.z};
  XmMatrix<T> m = zeroT<T>();
  const Vec3T<T> rows[3] = {r0, r1, r2};
  for (int k = 0; k < 3; ++k) {
    xm(m, 0, k) = rows[k].x;
    xm(m, 1, k) = rows[k].y;
    xm(m, 2, k) = rows[k].z;
    xm(m, 3, k) = dot(rows[k], negEye);
  }
  xm(m, 3, 3) = T(1);
  return m;
}

// XMMatrixLookAtLH(Eye, Focus, Up) = LookToLH(Eye, Focus - Eye, Up). LH, ROW vectors.
template <class T>
XmMatrix<T> lookAtLH(Vec3T<T> eye, Vec3T<T> focus, Vec3T<T> up) {
  return lookToLH<T>(eye, {focus.x - eye.x, focus.y - eye.y, focus.z - eye.z}, up);
}

// XMMatrixLookAtRH(Eye, Focus, Up) = LookToLH(Eye, Eye - Focus, Up): RH (looks down -z), ROW
// vectors.
template <class T>
XmMatrix<T> lookAtRH(Vec3T<T> eye, Vec3T<T> focus, Vec3T<T> up) {
  return lookToLH<T>(eye, {eye.x - focus.x, eye.y - focus.y, eye.z - focus.z}, up);
}

// XMMatrixMultiply(M1, M2) = M1 * M2 for row vectors (apply M1 first): the view * proj an app
// computes. SSE2 order: row i = (x * M2.r0 + z * M2.r2) + (y * M2.r1 + w * M2.r3), with
// (x, y, z, w) = M1.r[i]. (The _XM_NO_INTRINSICS_ path sums left to right instead.)
template <class T>
XmMatrix<T> multiply(const XmMatrix<T>& m1, const XmMatrix<T>& m2) {
  XmMatrix<T> out{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      xm(out, i, j) = (xm(m1, i, 0) * xm(m2, 0, j) + xm(m1, i, 2) * xm(m2, 2, j)) +
                      (xm(m1, i, 1) * xm(m2, 1, j) + xm(m1, i, 3) * xm(m2, 3, j));
  return out;
}

// XMMatrixTranspose.
template <class T>
XmMatrix<T> transposeXm(const XmMatrix<T>& m) {
  XmMatrix<T> out{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) xm(out, i, j) = xm(m, j, i);
  return out;
}

// (b) The 16 floats as they lie in memory (XMStoreFloat4x4 / memcpy of the XMMATRIX into a
// constant buffer): r[0].xyzw, r[1].xyzw, r[2].xyzw, r[3].xyzw.
template <class T>
Mat4 memoryOrder(const XmMatrix<T>& m) {
  Mat4 out{};
  for (std::size_t k = 0; k < 16; ++k) out[k] = static_cast<double>(m[k]);
  return out;
}

// (a) The mathematically equivalent GL matrix: G = M^T (column vectors), written column-major
// (element 4 * col + row = G(row, col) = M(col, row)). Same depth (ZO) and handedness as M. The
// values equal memoryOrder(m): see the note at the top.
template <class T>
Mat4 glColumnMajor(const XmMatrix<T>& m) {
  Mat4 out{};
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row)
      out[static_cast<std::size_t>(4 * col + row)] = static_cast<double>(xm(m, col, row));
  return out;
}

// The constant buffer of an app that uploads XMMatrixTranspose(M) (HLSL column_major packing with
// mul(v, M)): read as a GL mat4 it is the transpose of glColumnMajor(m).
template <class T>
Mat4 transposedUpload(const XmMatrix<T>& m) {
  return memoryOrder(transposeXm(m));
}

}  // namespace clipray::testing::engines::dxmath

#pragma once
// Oblique near-plane clipping: replace the depth row of a projection so that the near plane is an
// arbitrary view-space plane C (mirrors, water, portals), keeping the far corner of the frustum.
//   Eric Lengyel, "Oblique View Frustum Depth Projection and Clipping", Journal of Game
//   Development 1(2), 2005; code at terathon.com/code/oblique.html (OpenGL and Direct3D forms).
//   Implementations: mrdoob/three.js examples/jsm/objects/Reflector.js (and Water.js), the OpenGL
//   form below; Unity's Camera.CalculateObliqueMatrix (documented in the Unity scripting API).
//
// The plane C = (a, b, c, d) is in view space with the eye on its negative side (d < 0 when the
// eye is at the view-space origin); what is kept is C . p > 0. Points on C map to the near depth
// (z_ndc = -1 for NO, 0 for ZO, 1 for reversed ZO). The far plane becomes the plane through the
// old far corner q = M^-1 (sgn(C'x), sgn(C'y), z_far, 1), C' = M^-T C the plane in clip space, so
// the frustum's sides are unchanged; pixel rays that meet C behind the eye show nothing.

#include <array>
#include <cmath>
#include <optional>

#include "support/engines/Common.hpp"

namespace clipray::testing::engines::oblique {

enum class Depth { NO, ZO, ReversedZO };

// A plane transformed by a point transform M (p' = M p): C' = M^-T C. Use it to bring a world
// plane into view space (M = view-from-world) or a view plane into clip space.
inline std::optional<Vec4> transformPlane(const Mat4& m, const Vec4& plane) {
  const std::optional<Mat4> inv = inverse(m);
  if (!inv) return std::nullopt;
  return transform(transpose(*inv), plane);
}

// Lengyel's OpenGL form, operation order of terathon's code and three.js's Reflector, in T. Needs
// a GL-style perspective projection (RH, w = -z, [2][0] / [2][1] as the only off-axis terms, e.g.
// glm::perspectiveRH_NO, glFrustum, three.js, Godot, raylib): q uses sgn(C) for sgn(C'), which
// holds for those matrices. NO, RH, column vectors; the result is an oblique NO projection.
template <class T>
Mat4 lengyelOpenGL(const Mat4& projection, std::array<T, 4> c) {
  auto sgn = [](T a) { return a > T(0) ? T(1) : (a < T(0) ? T(-1) : T(0)); };
  Mat4T<T> m = fromMat4<T>(projection);
  std::array<T, 4> q{};
  q[0] = (sgn(c[0]) + m[8]) / m[0];
  q[1] = (sgn(c[1]) + m[9]) / m[5];
  q[2] = T(-1);
  q[3] = (T(1) + m[10]) / m[14];
  const T scale = T(2) / (c[0] * q[0] + c[1] * q[1] + c[2] * q[2] + c[3] * q[3]);
  m[2] = c[0] * scale;
  m[6] = c[1] * scale;
  m[10] = c[2] * scale + T(1);
  m[14] = c[3] * scale;
  return toMat4(m);
}

// The general form, in double, for any projection (RH or LH, finite or infinite far, off-axis):
// third row := (2 / C.q) C - row 3 for NO (Lengyel's OpenGL form), (1 / C.q) C for ZO (his
// Direct3D form), row 3 - (1 / C.q) C for reversed ZO (near plane -> 1, the old far corner -> 0).
// The depth argument is the convention the projection was built for; it is kept. Column vectors.
// nullopt when the projection is singular or C.q is 0.
inline std::optional<Mat4> obliqueNearPlane(const Mat4& projection, const Vec4& viewPlane,
                                            Depth depth) {
  const std::optional<Mat4> inv = inverse(projection);
  if (!inv) return std::nullopt;
  const Vec4 clipPlane = transform(transpose(*inv), viewPlane);
  auto sgn = [](double a) { return a > 0.0 ? 1.0 : (a < 0.0 ? -1.0 : 0.0); };
  const double zFar = depth == Depth::ReversedZO ? 0.0 : 1.0;
  const Vec4 q = transform(*inv, {sgn(clipPlane[0]), sgn(clipPlane[1]), zFar, 1.0});
  const double cq =
      viewPlane[0] * q[0] + viewPlane[1] * q[1] + viewPlane[2] * q[2] + viewPlane[3] * q[3];
  if (cq == 0.0 || !std::isfinite(cq)) return std::nullopt;
  Mat4 m = projection;
  for (int col = 0; col < 4; ++col) {
    const double ci = viewPlane[static_cast<std::size_t>(col)];
    const double w = el(projection, col, 3);
    double z = 0.0;
    switch (depth) {
      case Depth::NO:
        z = 2.0 / cq * ci - w;
        break;
      case Depth::ZO:
        z = 1.0 / cq * ci;
        break;
      case Depth::ReversedZO:
        z = w - 1.0 / cq * ci;
        break;
    }
    m[static_cast<std::size_t>(4 * col + 2)] = z;
  }
  return m;
}

}  // namespace clipray::testing::engines::oblique

#pragma once
// Builders for clip-from-view matrices in every depth convention clipray draws, in double.
// Right-handed view space: the camera looks down -z, w_clip = -z_view for perspective. Every
// matrix is column-major, p' = M * p (clipFromView * p_view, viewFromWorld * p_world).

#include <optional>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"

namespace clipray {

// Perspective projection built so that the near plane lands on mode.nearNdcZ() and the far plane
// on mode.farNdcZ(). farDistance == nullopt builds an infinite far plane. For an upper-left clip
// origin, clip y is negated (y down, as Direct3D and Vulkan build it), so the picture is upright.
glm::dmat4 perspectiveClipFromView(double fovYRadians, double aspect, double nearDistance,
                                   std::optional<double> farDistance, DepthMode builtFor);

// Orthographic projection of the box [left,right] x [bottom,top] x [-near,-far] (view space);
// clip y negated for an upper-left clip origin, as for perspective.
glm::dmat4 orthographicClipFromView(double left, double right, double bottom, double top,
                                    double nearDistance, double farDistance, DepthMode builtFor);

// Right-handed look-at: eye at the origin of view space, target on -z, up projected on +y.
glm::dmat4 viewFromWorldLookAt(const glm::dvec3& eye, const glm::dvec3& target,
                               const glm::dvec3& up);

// |det| after scaling each column to a largest magnitude of 1 and then each row to unit length:
// 1 for an orthogonal matrix, 0 for a singular one. Scaling the columns first keeps a camera far
// from the origin (whose translation column dwarfs the rest) from looking singular.
double scaledDeterminant(glm::dmat4 m);
double scaledDeterminant(glm::dmat3 m);

// Row r of a column-major matrix (rows are the clip-space planes: row 3 is w).
inline glm::dvec4 matrixRow(const glm::dmat4& m, int r) {
  return {m[0][r], m[1][r], m[2][r], m[3][r]};
}

}  // namespace clipray

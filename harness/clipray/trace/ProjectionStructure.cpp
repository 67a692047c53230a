// Projection structure (ProjectionStructure.hpp).

#include "clipray/trace/ProjectionStructure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clipray::trace {

double determinantSensitivity(const glm::dmat4& m) {
  const double determinant = glm::determinant(m);
  if (!(std::abs(determinant) > 0.0) || !std::isfinite(determinant)) {
    return std::numeric_limits<double>::infinity();
  }
  // C_ij = det * (M^-1)_ji, so |m_ij C_ij| / |det| = |m_ij (M^-1)_ji|.
  const glm::dmat4 inverse = glm::inverse(m);
  double sum = 0.0;
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) sum += std::abs(m[column][row] * inverse[row][column]);
  }
  return std::isfinite(sum) ? sum : std::numeric_limits<double>::infinity();
}

bool hasProjectionStructure(const glm::dmat4& m) {
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      if (!std::isfinite(m[column][row])) return false;
    }
  }
  // Singular to float precision: a planar shadow projection (rank 3, as glmark2's "ideas" scene
  // multiplies into its modelview) projects onto a plane and is no camera. Its determinant is
  // rounding noise, as large as the entries' own rounding moves it (a sensitivity of 1/u and
  // more); a camera's is at least 64 roundings clear of that. The sensitivity is invariant to
  // the scale of each row and column, so a pixel HUD ortho gluOrtho2D(0, W, 0, H) passes at any
  // W and H (its translation is as large as its scale is small), as does a camera far from the
  // origin until float32 can no longer hold the depth row at its eye.
  if (!(determinantSensitivity(m) * 0x1p-24 < 1.0 / 64.0)) return false;
  const bool perspective = m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0;
  const glm::dmat3 linear(m);
  if (perspective) {
    // A normal matrix, transpose(inverse(modelView)) as a mat4, has the modelview's translation
    // in row 3 and none in column 3: the transpose of an orientation-preserving affine map, no
    // camera. (A perspective projection maps depth through column 3: z_clip = a z + b w, b != 0.)
    const bool transposedAffine = m[3][0] == 0.0 && m[3][1] == 0.0 && m[3][2] == 0.0 &&
                                  m[3][3] != 0.0 && glm::determinant(linear) > 0.0;
    return !transposedAffine;
  }
  if (glm::determinant(linear) >= 0.0) return false;
  // A mirrored model or view matrix (a reflection, scale(1, -1, 1)) also reverses orientation,
  // but it scales every direction alike: its columns are orthogonal and of one length. An
  // orthographic projection scales x, y and depth by 2/width, 2/height and 2/depth, which differ
  // unless its view volume is a cube (glOrtho(-1, 1, -1, 1, -1, 1)). Such a cube volume is told
  // from a mirror by glOrtho's own shape: on-axis, with z alone flipped (x and y kept), where a
  // reflection in a floor or wall flips x or y. (A model matrix scale(1, 1, -1) has that shape
  // too and is taken for a projection; a cube volume times a rotating view is still missed.)
  const glm::dmat3 gram = glm::transpose(linear) * linear;
  const double scale = (gram[0][0] + gram[1][1] + gram[2][2]) / 3.0;
  const double tolerance = 1e-5 * scale;  // 7-digit decimals of the dump
  bool similarity = true;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (std::abs(gram[i][j] - (i == j ? scale : 0.0)) > tolerance) similarity = false;
    }
  }
  if (!similarity) return true;
  const bool onAxis = std::abs(linear[0][1]) + std::abs(linear[0][2]) + std::abs(linear[1][0]) +
                          std::abs(linear[1][2]) + std::abs(linear[2][0]) +
                          std::abs(linear[2][1]) <=
                      1e-5 * std::sqrt(scale);
  return onAxis && linear[0][0] > 0.0 && linear[1][1] > 0.0 && linear[2][2] < 0.0;
}

bool hasReversedOrthographicStructure(const glm::dmat4& m) {
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      if (!std::isfinite(m[column][row])) return false;
    }
  }
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) return false;
  if (!(determinantSensitivity(m) * 0x1p-24 < 1.0 / 64.0)) return false;
  const glm::dmat3 linear(m);
  const double sx = linear[0][0], sy = linear[1][1], sz = linear[2][2];
  const double scale = std::max({std::abs(sx), std::abs(sy), std::abs(sz)});
  const double offAxis = std::abs(linear[0][1]) + std::abs(linear[0][2]) + std::abs(linear[1][0]) +
                         std::abs(linear[1][2]) + std::abs(linear[2][0]) + std::abs(linear[2][1]);
  if (offAxis > 1e-5 * scale) return false;  // 7-digit decimals of the dump
  if (!(sx > 0.0 && sy != 0.0 && sz > 0.0) || glm::determinant(linear) <= 0.0) return false;
  // Unequal scales: a view volume's width, height and depth differ where a similarity's do not.
  const double tolerance = 1e-5 * scale;
  return std::abs(std::abs(sx) - std::abs(sz)) > tolerance ||
         std::abs(std::abs(sy) - std::abs(sz)) > tolerance;
}

}  // namespace clipray::trace

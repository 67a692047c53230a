#pragma once
// Which 4x4 matrices a trace's draw hands over as projections: judged by structure, never by a
// uniform's name or the size of its translation.

#include <glm/glm.hpp>

namespace clipray::trace {

// Perspective (row 3 has an xyz part, and the matrix is not the transpose of an affine map such
// as a normal matrix) or orthographic (an affine map whose linear part reverses
// orientation: GL's clip space is left-handed, so glOrtho and every GL orthographic projection
// flips z while a model or view matrix does not); finite and invertible either way.
bool hasProjectionStructure(const glm::dmat4& matrix);

// How far the float rounding of the entries can move the determinant, relative to it: the sum
// over the entries of |m_ij C_ij| / |det| (C the cofactors; Sum m_ij C_ij = 4 det, so it is at
// least 4, and exactly 4 for glOrtho and glFrustum at any size). Infinite for a singular matrix.
double determinantSensitivity(const glm::dmat4& matrix);

}  // namespace clipray::trace

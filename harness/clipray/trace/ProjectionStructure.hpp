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

// A reversed-Z orthographic projection (near -> 1, far -> 0 or -1: three.js's
// makeOrthographic with reversedDepth, src/math/Matrix4.js): an affine map whose z scale is
// positive, so that, unlike every other GL orthographic projection, it keeps orientation, as a
// model or view matrix does. Told from those by glOrtho's own shape: on-axis, x, y and z scaled
// unequally (a rigid or uniformly scaled view is a similarity), finite and invertible. A
// non-uniformly scaled model seen by an axis-aligned view has that shape too: take such a matrix
// for a projection only in a reversed-Z frame (GL_GREATER or GL_GEQUAL over a depth cleared to
// 0) and where a draw has no matrix of hasProjectionStructure.
bool hasReversedOrthographicStructure(const glm::dmat4& matrix);

// How far the float rounding of the entries can move the determinant, relative to it: the sum
// over the entries of |m_ij C_ij| / |det| (C the cofactors; Sum m_ij C_ij = 4 det, so it is at
// least 4, and exactly 4 for glOrtho and glFrustum at any size). Infinite for a singular matrix.
double determinantSensitivity(const glm::dmat4& matrix);

}  // namespace clipray::trace

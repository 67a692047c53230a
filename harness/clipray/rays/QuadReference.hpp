#pragma once
// The reference every ray method is measured against: the exact camera ray of a matrix's entries
// (as stored: pass float entries widened to double), evaluated in __float128 (113-bit mantissa,
// software arithmetic from libgcc/libquadmath). Rounding in the reference is ~1e-34 relative, far
// below any error a float or double method can make, so "error" means the method's own error.
// clipFromWorld: column-major, p_clip = clipFromWorld * p_world, built for the DepthMode given.
//
// Results are handed out as double-double (hi + lo) so the metrics can subtract a double result
// from them without losing the bits that a double method's 1e-16 errors live in.

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/Ray.hpp"

namespace clipray {

__extension__ typedef __float128 Float128;  // __extension__: a GNU type, keeps -Wpedantic quiet

// Column-major like glm: m[column][row].
struct QuadMat4 {
  Float128 m[4][4];
};
struct QuadVec3 {
  Float128 x, y, z;
};
struct QuadVec4 {
  Float128 x, y, z, w;
};

QuadMat4 toQuad(const glm::dmat4& matrix);
// Gauss-Jordan with partial pivoting; nullopt when a pivot is exactly zero (singular).
std::optional<QuadMat4> inverseQuad(const QuadMat4& matrix);
QuadVec4 quadRow(const QuadMat4& matrix, int row);
QuadVec4 quadColumn(const QuadMat4& matrix, int column);
QuadVec3 cross(const QuadVec3& a, const QuadVec3& b);
Float128 dot(const QuadVec3& a, const QuadVec3& b);
Float128 dot(const QuadVec4& a, const QuadVec4& b);
inline QuadVec3 xyz(const QuadVec4& v) {
  return {v.x, v.y, v.z};
}
inline double toDouble(Float128 q) {
  return static_cast<double>(q);
}
glm::dvec3 toDouble(const QuadVec3& v);
// det(matrix), exact to quad rounding (Laplace expansion along row 0).
Float128 determinantQuad(const QuadMat4& matrix);

// The sign (+1 or -1) that turns the plane-cross direction x' P + y' Q + R (P = my x mw,
// Q = mw x mx, R = mx x my) into the ray's: into the view volume through the near plane wherever
// the pixel has a ray, i.e. sign(s det(clipFromWorld)), s = -1 for reversed-Z. One sign for the
// whole camera: for a perspective camera it is w growing along d (away from the eye) when the eye
// lies on the clipped side of the near plane, as for every ordinary camera and Lengyel's oblique
// near plane (whose own dot with d changes sign at its horizon), and w shrinking (towards the eye)
// when a matrix is drawn under a convention whose near plane lies beyond the eye's side (a NO
// matrix under reversed-Z: the ray runs from its far plane back towards the eye, as the GREATER
// depth test sees it). 0 for a singular matrix.
int robustDirectionSign(const glm::dmat4& clipFromWorld, DepthMode mode);

// The camera a clipFromWorld matrix describes, derived in quad from the matrix alone
// (docs/bench.md: "the projection type, eye, near/far and fov follow from the matrix").
struct ProjectionFacts {
  bool parallel = false;      // row 3 has no xyz part: w is constant (orthographic-like)
  glm::dvec3 eye{0.0};        // perspective: the null vector of rows 0, 1, 3
  glm::dvec3 forward{0.0};    // unit direction of the centre ray (clip xy = 0, 0)
  double nearDistance = 0.0;  // along the centre ray, from the eye (perspective) or signed;
                              // +inf when the centre pixel has no ray (oblique near plane)
  double farDistance = 0.0;   // +inf for an infinite far plane
  double fovYDegrees = 0.0;   // angle between the rays at clip y = -1 and y = +1 (x = 0)
  bool mirrored = false;      // det(clipFromWorld) < 0: the image is mirrored
  double determinant = 0.0;
};

// Describes the camera, or returns the reason the matrix is not a usable projection under `mode`
// (singular, a pixel ray that never meets the near plane, a near plane behind the eye, ...). A
// perspective matrix with an oblique near plane (Lengyel's) whose horizon is in view is a
// projection: some pixels have no ray, as long as one has.
struct ProjectionCheck {
  std::optional<ProjectionFacts> facts;
  std::string problem;  // set when facts is empty
};
ProjectionCheck describeProjection(const glm::dmat4& clipFromWorld, DepthMode mode);

// A double-double number: value = hi + lo, |lo| <= ulp(hi) / 2.
struct DoubleDouble {
  double hi = 0.0;
  double lo = 0.0;
};

struct ReferenceRay {
  DoubleDouble origin[3];
  DoubleDouble direction[3];  // unit length to ~1e-32
  // +inf for an infinite far plane; kNoRayTMax where the pixel has no ray (its line of sight
  // meets the near plane behind the eye: beyond an oblique near plane's horizon), and then the
  // other fields are zero.
  double tMax = 0.0;
  bool hasRay() const { return tMax >= 0.0; }
  // Units the errors are reported in, at this pixel (docs/bench.md):
  double pixelAngle = 0.0;      // radians between this pixel's ray and its nearer neighbour's;
                                // parallel projections: footprint / depth of the view volume
  double pixelFootprint = 0.0;  // one pixel's width on the near plane, across the ray
};

class QuadReference {
 public:
  // clipFromWorld holds the exact entries to be referenced (float entries widened to double for
  // the float methods). It must describe a projection (describeProjection succeeded).
  QuadReference(const glm::dmat4& clipFromWorld, DepthMode mode, Viewport viewport);

  // The exact rays of row j (pixel centres, lower-left origin), width() entries.
  void row(int j, std::vector<ReferenceRay>& out) const;
  Viewport viewport() const { return viewport_; }
  bool parallel() const { return parallel_; }

 private:
  Viewport viewport_;
  DepthMode mode_;
  bool parallel_ = false;
  // d(x', y') = x' P + y' Q + R (plane-cross, seed 002 listing 3), exact in quad.
  QuadVec3 p_, q_, r_;
  // facingSign_ * dot(facingNormal_, d) > 0: perspective, the xyz of row 3 and
  // robustDirectionSign times the sign of dot(mw, d) (constant over the frame); parallel, the xyz
  // of rowZ - z_near rowW and +1, or -1 for reversed-Z.
  QuadVec3 facingNormal_;
  Float128 facingSign_;
  QuadVec3 farNormal_;  // xyz of rowZ - z_far rowW
  // Near-plane point N(x', y') = worldFromClip (x', y', z_near, 1) = x' c0 + y' c1 + c23.
  QuadVec4 c0_, c1_, c23_;
};

}  // namespace clipray

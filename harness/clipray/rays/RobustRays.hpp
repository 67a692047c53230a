#pragma once
// The `robust` ray method (DESIGN.md section 2): direction from the plane-cross product of rows of
// clipFromWorld, its sign fixed by the near plane (which always exists), origin on the near plane
// the rasterizer clips at, tMax at the far plane or +inf. Works for perspective, orthographic,
// oblique, mirrored, reversed-Z and infinite far without per-case switches from the caller.

#include <span>

#include <glm/glm.hpp>

#include "clipray/math/Conventions.hpp"
#include "clipray/rays/Ray.hpp"

namespace clipray {

class RobustRayGenerator {
 public:
  // Precomputes per camera. clipFromWorld must be invertible (the scene loader checks).
  RobustRayGenerator(const glm::dmat4& clipFromWorld, DepthMode mode);

  // Ray through clip-space xy (x', y' in [-1, 1]). Never throws.
  Ray generate(glm::dvec2 clipXY) const noexcept;
  Ray generateForPixel(int i, int j, Viewport viewport) const noexcept {
    return generate(clipXYOfPixelCentre(i, j, viewport));
  }
  // rays[k] = generate({clipX[k], clipY}) for a whole row, bit for bit, with the terms that only
  // depend on the row computed once, and four pixels per instruction where the CPU has AVX2 and
  // FMA (the same operations in the same order: the same bits).
  void generateRow(double clipY, std::span<const double> clipX, Ray* rays) const noexcept;
  // Whether generateRow may use its AVX2 + FMA kernels (the default, where the CPU has them).
  // Tests pin the portable loop too. Not thread-safe with concurrent generateRow calls.
  static void allowRowKernels(bool allowed);

  const glm::dmat4& clipFromWorld() const { return clipFromWorld_; }
  const glm::dmat4& worldFromClip() const { return worldFromClip_; }
  DepthMode mode() const { return mode_; }
  // Row 3 of the matrix has no xyz part: w is constant, a parallel projection.
  bool isParallel() const { return parallel_; }

 private:
  // The rest of generate() once the direction d and the near point in world space (homogeneous)
  // are known.
  Ray finishRay(glm::dvec3 d, const glm::dvec4& nearPointWorld) const noexcept;
  glm::dmat4 clipFromWorld_;
  glm::dmat4 worldFromClip_;
  DepthMode mode_;
  // Precomputed plane-cross terms (seed 002 listing 3): d = x'(my x mw) + y'(mw x mx) + mx x my.
  glm::dvec3 myCrossMw_, mwCrossMx_, mxCrossMy_;
  glm::dvec4 nearPlane_;  // row2 - z_near * row3: zero on the near clip plane
  glm::dvec4 farPlane_;   // row2 - z_far * row3
  double nearSign_;       // +1, or -1 for reversed-Z: sign of nearPlane inside the frustum
  bool parallel_;
};

}  // namespace clipray

#pragma once
// The `robust` ray method (docs/bench.md): direction from the plane-cross product of rows of
// clipFromWorld, one sign per camera (where clip w grows, in front of the eye, for every ordinary
// camera; a parallel projection, whose w is constant, takes it from its near plane), origin on the
// near plane the rasterizer clips at, tMax at the far plane or +inf. Works for perspective,
// orthographic, oblique (Lengyel's near plane, horizon in view), mirrored, reversed-Z and infinite
// far without per-case switches from the caller. A pixel whose line of sight never crosses the near
// plane in front of the eye (beyond the horizon of an oblique near plane, or a matrix drawn under a
// convention whose near plane lies behind the eye) has no ray: tMax = kNoRayTMax. clipFromWorld:
// column-major, p_clip = clipFromWorld * p_world, built for the DepthMode given.

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/Ray.hpp"

namespace clipray {

// GL_DEPTH_CLAMP on the raster side: nothing is clipped at the near and far planes, so the rays
// reach what the picture shows in front of the near plane. A perspective camera's rays start at
// the eye (GL still clips at w = 0: -w <= x, y <= w holds nowhere behind it); a parallel one has
// no eye, and its rays start parallelReach behind the near plane (what the scene's extent there
// needs). They end at the far plane unless beyondFar: what lies beyond it is drawn at the far end
// of the depth range, except where that end is the depth buffer's clear value, which a strict
// depth test (GL_LESS, GL_GREATER) never passes.
struct DepthClampRays {
  bool enabled = false;
  double parallelReach = 0.0;
  bool beyondFar = false;
};

// Cuts a ray to the part of its interval that every user clip plane keeps (world space, kept where
// dot(plane, (p, 1)) >= 0, Camera::clipPlanes): the origin moves forward along the same line,
// tMax shortens, and a line of sight the planes leave nothing of gets tMax 0 (it hits nothing).
// A ray without a ray (tMax < 0) or no planes: unchanged. What RobustRayGenerator does to its
// rays; any other picking ray gets the same cut from it.
void cutToClipPlanes(Ray& ray, std::span<const glm::dvec4> clipPlanes) noexcept;

class RobustRayGenerator {
 public:
  // Precomputes per camera. The matrix and mode as the frame is drawn, under either clip origin;
  // pixels and clip xy are a lower-left origin's (clipFromWorld() and mode() give the camera in
  // those terms: lowerLeftClipFromWorld). The matrix must be invertible (the scene loader checks).
  // clipPlanes: the camera's user clip planes (world space, kept where dot(plane, (p, 1)) >= 0,
  // Camera::clipPlanes): each ray is cut to the part of its interval that every plane keeps (its
  // origin moved forward along the same line, tMax shortened), and a line of sight that no plane
  // leaves anything of gets tMax 0 (a ray that hits nothing).
  // depthClamp: the rays GL_DEPTH_CLAMP needs (DepthClampRays), cut by the clip planes after.
  RobustRayGenerator(const glm::dmat4& drawnClipFromWorld, DepthMode drawnMode,
                     std::span<const glm::dvec4> clipPlanes = {}, DepthClampRays depthClamp = {});

  // Ray through clip-space xy (x', y' in [-1, 1]). Never throws.
  Ray generate(glm::dvec2 clipXY) const noexcept;
  Ray generateForPixel(int i, int j, Viewport viewport) const noexcept {
    return generate(clipXYOfPixelCentre(i, j, viewport));
  }
  // What the row generator computes once per row: the direction's and the near point's parts
  // that depend on clip y alone (kept per row by PixelCentreRays, so that a piece of a row can be
  // generated at a time).
  struct RowTerms {
    glm::dvec3 direction;  // fma(y, mw x mx, mx x my)
    glm::dvec4 nearPoint;  // worldFromClip column 1 times y
  };
  RowTerms rowTerms(double clipY) const noexcept;
  // rays[k] = generate({clipX[k], clipY}) for the row whose terms are `row`, bit for bit, four
  // pixels per instruction where the CPU has AVX2 and FMA (the same operations in the same order:
  // the same bits).
  void generateRow(const RowTerms& row, std::span<const double> clipX, Ray* rays) const noexcept;
  // Whether generateRow may use its AVX2 + FMA kernels (the default, where the CPU has them).
  // Tests pin the portable loop too. Not thread-safe with concurrent generateRow calls.
  static void allowRowKernels(bool allowed);

  const glm::dmat4& clipFromWorld() const { return clipFromWorld_; }
  const glm::dmat4& worldFromClip() const { return worldFromClip_; }
  DepthMode mode() const { return mode_; }
  // The user clip planes its rays are cut by (world space, kept where dot(plane, (p, 1)) >= 0).
  std::span<const glm::dvec4> clipPlanes() const { return clipPlanes_; }
  // Row 3 of the matrix has no xyz part: w is constant, a parallel projection.
  bool isParallel() const { return parallel_; }
  // The rays GL_DEPTH_CLAMP needs, when enabled (DepthClampRays); then a perspective camera's rays
  // all start at eye(), the eye as computed (worldFromClip column 2 over its w).
  const DepthClampRays& depthClamp() const { return depthClamp_; }
  const glm::dvec3& eye() const { return eye_; }
  // The sign s of the direction test s * dot(facing, d) > 0 (see facingNormal_); the GLSL rays
  // of the analytic primitives (shaders/camera_rays.glsl) take it as a uniform.
  double facingSign() const { return facingSign_; }

 private:
  // The rest of generate() once the direction d and the near point in world space (homogeneous)
  // are known.
  Ray finishRay(glm::dvec3 d, const glm::dvec4& nearPointWorld) const noexcept;
  // A finished ray moved back to where depth clamp's drawing starts (DepthClampRays).
  void reachForDepthClamp(Ray& ray) const noexcept;
  // What finishRay does after the near-plane ray: depth clamp's reach, then the planes' cut.
  void finishInterval(Ray& ray) const noexcept {
    if (depthClamp_.enabled) reachForDepthClamp(ray);
    cutToClipPlanes(ray, clipPlanes_);
  }
  std::vector<glm::dvec4> clipPlanes_;
  DepthClampRays depthClamp_;
  glm::dvec3 eye_{0.0};  // a perspective camera's eye (depth clamp's origin)
  glm::dmat4 clipFromWorld_;
  glm::dmat4 worldFromClip_;
  DepthMode mode_;
  // Precomputed plane-cross terms (seed 002 listing 3): d = x'(my x mw) + y'(mw x mx) + mx x my.
  glm::dvec3 myCrossMw_, mwCrossMx_, mxCrossMy_;
  glm::dvec4 depthPart_;  // worldFromClip columns 2 and 3 times (z_near, 1): the same every row
  glm::dvec4 nearPlane_;  // row2 - z_near * row3: zero on the near clip plane
  glm::dvec4 farPlane_;   // row2 - z_far * row3
  // The direction d must satisfy facingSign_ * dot(facingNormal_, d) > 0: perspective, the xyz of
  // row 3 (dot(mw, d) = det(mx, my, mw): one sign over the frame) with robustDirectionSign's sign
  // (QuadReference.hpp): away from the eye, where w grows, whatever the near plane's tilt, unless
  // the near plane lies on the eye's visible side (a NO matrix under reversed-Z: towards it);
  // parallel (w constant), the near plane's normal with +1, or -1 for reversed-Z. Either way d
  // enters the view volume through the near plane wherever the pixel has a ray.
  glm::dvec3 facingNormal_;
  double facingSign_;
  bool parallel_;
};

// The robust rays through the pixel centres of a viewport, computed where they are needed instead
// of stored. A 1920x1080 frame of rays is 116 MB (464 MB at 3840x2160): writing it once and
// reading it back in the intersection and again in the compare cost about what computing each
// ray twice does, and the first run of a process paid for every fresh page of it on top.
class PixelCentreRays {
 public:
  PixelCentreRays(const glm::dmat4& clipFromWorld, DepthMode mode, Viewport viewport,
                  std::span<const glm::dvec4> clipPlanes = {}, DepthClampRays depthClamp = {});

  // rays[k] = generator().generateForPixel(xBegin + k, y, viewport()), bit for bit, for
  // k < count (the pixels must lie in the viewport).
  void row(int y, int xBegin, int count, Ray* rays) const noexcept;

  const RobustRayGenerator& generator() const { return generator_; }
  Viewport viewport() const { return viewport_; }

 private:
  RobustRayGenerator generator_;
  Viewport viewport_;
  // clipXYOfPixelCentre's x depends on the column only: computed once per column.
  std::vector<double> clipXOfColumn_;
  std::vector<RobustRayGenerator::RowTerms> rowTermsOfRow_;
};

}  // namespace clipray

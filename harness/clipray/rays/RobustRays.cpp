#include "clipray/rays/RobustRays.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "clipray/math/Projections.hpp"

namespace clipray {

RobustRayGenerator::RobustRayGenerator(const glm::dmat4& clipFromWorld, DepthMode mode)
    : clipFromWorld_(clipFromWorld), worldFromClip_(glm::inverse(clipFromWorld)), mode_(mode) {
  const glm::dvec4 rowX = matrixRow(clipFromWorld, 0);
  const glm::dvec4 rowY = matrixRow(clipFromWorld, 1);
  const glm::dvec4 rowZ = matrixRow(clipFromWorld, 2);
  const glm::dvec4 rowW = matrixRow(clipFromWorld, 3);
  const glm::dvec3 mx(rowX), my(rowY), mw(rowW);
  myCrossMw_ = glm::cross(my, mw);
  mwCrossMx_ = glm::cross(mw, mx);
  mxCrossMy_ = glm::cross(mx, my);
  nearPlane_ = rowZ - mode.nearNdcZ() * rowW;
  farPlane_ = rowZ - mode.farNdcZ() * rowW;
  // Inside the clip volume z_n w <= z <= w: the plane z - z_n w is >= 0 for the classic near
  // plane; for reversed-Z the near plane is z - w, which is <= 0 inside.
  nearSign_ = mode.reversed ? -1.0 : 1.0;
  parallel_ = mw == glm::dvec3(0.0);
}

Ray RobustRayGenerator::generate(glm::dvec2 clipXY) const noexcept {
  const double x = clipXY.x;
  const double y = clipXY.y;
  glm::dvec3 d;
  for (int k = 0; k < 3; ++k) {
    d[k] = std::fma(x, myCrossMw_[k], std::fma(y, mwCrossMx_[k], mxCrossMy_[k]));
  }
  const glm::dvec4 nearPointClip(x, y, mode_.nearNdcZ(), 1.0);
  return finishRay(d, worldFromClip_ * nearPointClip);
}

namespace {

// Pixels per block of generateRow: their directions are computed together, then finished.
constexpr std::size_t kRowBlock = 64;

// direction[k][c] = fma(clipX[k], a[c], b[c]): the per-pixel part of generate()'s direction.
// fma is correctly rounded, so the instruction and libm's fma give the same bits; only the call
// differs (a library call per component where the compiler may not assume FMA hardware).
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("fma"))) void directionsWithFmaInstructions(const double* clipX,
                                                                  std::size_t count,
                                                                  const glm::dvec3& a,
                                                                  const glm::dvec3& b,
                                                                  glm::dvec3* direction) {
  for (std::size_t k = 0; k < count; ++k) {
    for (int c = 0; c < 3; ++c) direction[k][c] = __builtin_fma(clipX[k], a[c], b[c]);
  }
}
bool cpuHasFma() {
  static const bool fma = __builtin_cpu_supports("fma");
  return fma;
}
#else
void directionsWithFmaInstructions(const double*, std::size_t, const glm::dvec3&, const glm::dvec3&,
                                   glm::dvec3*) {}
bool cpuHasFma() {
  return false;
}
#endif

void directionsOfRow(const double* clipX, std::size_t count, const glm::dvec3& a,
                     const glm::dvec3& b, glm::dvec3* direction) {
  if (cpuHasFma()) {
    directionsWithFmaInstructions(clipX, count, a, b, direction);
    return;
  }
  for (std::size_t k = 0; k < count; ++k) {
    for (int c = 0; c < 3; ++c) direction[k][c] = std::fma(clipX[k], a[c], b[c]);
  }
}

}  // namespace

void RobustRayGenerator::generateRow(double clipY, std::span<const double> clipX,
                                     Ray* rays) const noexcept {
  // generate() computes d[c] = fma(x, myCrossMw, fma(y, mwCrossMx, mxCrossMy)) and the near point
  // as glm's matrix-vector product ((M0 x + M1 y) + (M2 z + M3 w)): the inner fma, M1 y and
  // (M2 z + M3 w) are the same for the whole row. Computed once, the same operations on the same
  // operands give the same bits.
  glm::dvec3 rowTerm;
  for (int c = 0; c < 3; ++c) rowTerm[c] = std::fma(clipY, mwCrossMx_[c], mxCrossMy_[c]);
  const glm::dvec4 rowPart = worldFromClip_[1] * clipY;
  const glm::dvec4 depthPart = worldFromClip_[2] * mode_.nearNdcZ() + worldFromClip_[3] * 1.0;
  glm::dvec3 direction[kRowBlock];
  for (std::size_t first = 0; first < clipX.size(); first += kRowBlock) {
    const std::size_t count = std::min(kRowBlock, clipX.size() - first);
    directionsOfRow(clipX.data() + first, count, myCrossMw_, rowTerm, direction);
    for (std::size_t k = 0; k < count; ++k) {
      const glm::dvec4 nearPointWorld =
          (worldFromClip_[0] * clipX[first + k] + rowPart) + depthPart;
      rays[first + k] = finishRay(direction[k], nearPointWorld);
    }
  }
}

Ray RobustRayGenerator::finishRay(glm::dvec3 d, const glm::dvec4& nearPointWorld) const noexcept {
  // The direction must enter the frustum through the near plane.
  if (nearSign_ * glm::dot(glm::dvec3(nearPlane_), d) < 0.0) d = -d;
  d /= std::sqrt(glm::dot(d, d));

  Ray ray;
  ray.origin = glm::dvec3(nearPointWorld) / nearPointWorld.w;
  ray.direction = d;
  // The near point must lie in front of the eye (clip w = 1 / w_world > 0) and be finite. It does
  // not when a matrix is drawn under conventions it was not built for in the reversed sense (a
  // reversed-Z matrix under NO puts z = -1 behind the eye, a NO infinite matrix under reversed-Z
  // puts z = 1 at infinity): no ray, rather than one from behind the camera.
  if (!(nearPointWorld.w > 0.0) || !std::isfinite(ray.origin.x + ray.origin.y + ray.origin.z)) {
    ray.tMax = kNoRayTMax;
    return ray;
  }

  // Far plane: F . (o + t d, 1) = 0. A zero denominator or a non-positive / non-finite t means the
  // far plane lies at infinity (an infinite-far matrix makes F's xyz exactly zero).
  const double denominator = glm::dot(glm::dvec3(farPlane_), d);
  const double numerator = glm::dot(farPlane_, glm::dvec4(ray.origin, 1.0));
  const double t = -numerator / denominator;
  ray.tMax = (denominator != 0.0 && t > 0.0 && std::isfinite(t))
                 ? t
                 : std::numeric_limits<double>::infinity();
  return ray;
}

}  // namespace clipray

#include "clipray/math/Projections.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace clipray {

glm::dmat4 perspectiveClipFromView(double fovYRadians, double aspect, double nearDistance,
                                   std::optional<double> farDistance, DepthMode builtFor) {
  const double focal = 1.0 / std::tan(fovYRadians / 2.0);
  const double n = nearDistance;
  glm::dmat4 m(0.0);
  m[0][0] = focal / aspect;
  // Built for an upper-left clip origin, y points down in clip space (as Direct3D's and
  // Vulkan's projections do): the picture comes out upright.
  m[1][1] = builtFor.origin == ClipOrigin::UpperLeft ? -focal : focal;
  m[2][3] = -1.0;  // row 3 (w_clip) = -z_view: the perspective divide by view distance
  // Row 2 (z_clip) = m[2][2] * z_view + m[3][2]; closed forms avoid the cancellation of deriving
  // one convention from another.
  if (!farDistance) {
    if (builtFor.reversed) {  // z_ndc = n / distance: 1 at the near plane, 0 at infinity
      m[2][2] = 0.0;
      m[3][2] = n;
    } else if (builtFor.convention == DepthConvention::ZeroToOne) {  // z_ndc = 1 - n / distance
      m[2][2] = -1.0;
      m[3][2] = -n;
    } else {  // z_ndc = 1 - 2n / distance
      m[2][2] = -1.0;
      m[3][2] = -2.0 * n;
    }
    return m;
  }
  const double f = *farDistance;
  if (builtFor.reversed) {
    m[2][2] = n / (f - n);
    m[3][2] = f * n / (f - n);
  } else if (builtFor.convention == DepthConvention::ZeroToOne) {
    m[2][2] = -f / (f - n);
    m[3][2] = -f * n / (f - n);
  } else {
    m[2][2] = -(f + n) / (f - n);
    m[3][2] = -2.0 * f * n / (f - n);
  }
  return m;
}

glm::dmat4 orthographicClipFromView(double left, double right, double bottom, double top,
                                    double nearDistance, double farDistance, DepthMode builtFor) {
  const double n = nearDistance;
  const double f = farDistance;
  glm::dmat4 m(1.0);
  m[0][0] = 2.0 / (right - left);
  m[1][1] = 2.0 / (top - bottom);
  m[3][0] = -(right + left) / (right - left);
  m[3][1] = -(top + bottom) / (top - bottom);
  if (builtFor.origin == ClipOrigin::UpperLeft) {  // y down in clip space, as for perspective
    m[1][1] = -m[1][1];
    m[3][1] = -m[3][1];
  }
  if (builtFor.reversed) {  // z_ndc: 1 at z_view = -n, 0 at z_view = -f
    m[2][2] = 1.0 / (f - n);
    m[3][2] = f / (f - n);
  } else if (builtFor.convention == DepthConvention::ZeroToOne) {
    m[2][2] = -1.0 / (f - n);
    m[3][2] = -n / (f - n);
  } else {
    m[2][2] = -2.0 / (f - n);
    m[3][2] = -(f + n) / (f - n);
  }
  return m;
}

namespace {
template <int N>
double scaledDeterminantOf(glm::mat<N, N, double> m) {
  for (int c = 0; c < N; ++c) {
    double largest = 0.0;
    for (int r = 0; r < N; ++r) largest = std::max(largest, std::fabs(m[c][r]));
    if (largest == 0.0) return 0.0;
    m[c] /= largest;
  }
  for (int r = 0; r < N; ++r) {
    double sum = 0.0;
    for (int c = 0; c < N; ++c) sum += m[c][r] * m[c][r];
    if (sum == 0.0) return 0.0;
    const double norm = std::sqrt(sum);
    for (int c = 0; c < N; ++c) m[c][r] /= norm;
  }
  return std::fabs(glm::determinant(m));
}
}  // namespace

double scaledDeterminant(glm::dmat4 m) {
  return scaledDeterminantOf<4>(m);
}
double scaledDeterminant(glm::dmat3 m) {
  return scaledDeterminantOf<3>(m);
}

glm::dmat4 viewFromWorldLookAt(const glm::dvec3& eye, const glm::dvec3& target,
                               const glm::dvec3& up) {
  return glm::lookAtRH(eye, target, up);
}

}  // namespace clipray

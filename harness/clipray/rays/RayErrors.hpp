#pragma once
// Error metrics of computed rays against the quad-precision reference (docs/bench.md):
// - angle: angle between the computed and the exact direction, in units of one pixel's angle;
// - origin lateral: distance of the computed origin from the exact ray line, in pixel footprints
//   on the near plane (sliding along the ray is harmless, so only the part across counts);
// - t_max: relative error (an infinite reference wants +inf: anything finite is an infinite error);
// - non-finite rays (any NaN/inf in origin or direction, or a NaN t_max) and backward rays
//   (pointing away from the exact direction);
// - pixels without a ray: where the exact ray does not exist (the line of sight meets the near
//   plane behind the eye, beyond an oblique near plane's horizon) the pixel is counted as no_ray
//   and measured no further; a method that gives a ray there, or none where the exact ray
//   exists, is counted as a no-ray disagreement.
// Medians come from a log-spaced histogram (64 bins per decade, so within 2% of the exact median):
// a 1920x1080 grid for 16 method/precision pairs would not fit in memory as raw samples.

#include <array>
#include <cstdint>
#include <vector>

#include "clipray/rays/QuadReference.hpp"
#include "clipray/rays/RayMethods.hpp"

namespace clipray {

class LogHistogram {
 public:
  void add(double value);
  void merge(const LogHistogram& other);
  double median() const;  // 0 when empty
  std::uint64_t count() const { return count_; }

 private:
  static constexpr int kBinsPerDecade = 64;
  static constexpr int kMinDecade = -24;  // values below 1e-24 count as the lowest bin
  static constexpr int kDecades = 40;     // up to 1e16; larger values land in the top bin
  std::array<std::uint64_t, kBinsPerDecade * kDecades> bins_{};
  std::uint64_t zeros_ = 0;
  std::uint64_t count_ = 0;
};

struct ErrorStats {
  double max = 0.0;
  double p50 = 0.0;
};

struct MethodErrors {
  ErrorStats anglePx;            // over rays with finite directions
  ErrorStats originLateralPx;    // over rays with finite origins
  double tMaxRelativeMax = 0.0;  // NaN when the method gives no t_max
  std::uint64_t nonfinite = 0;
  std::uint64_t backward = 0;
  std::uint64_t rays = 0;           // pixels measured (the exact ray and the method's exist)
  std::uint64_t noRay = 0;          // pixels without an exact ray
  std::uint64_t noRayDisagree = 0;  // the method gives a ray iff the exact ray does not exist
};

class ErrorAccumulator {
 public:
  explicit ErrorAccumulator(bool measureTMax = true) : measureTMax_(measureTMax) {}
  // One row of computed rays against the same row of reference rays.
  template <typename T>
  void addRow(const std::vector<ReferenceRay>& reference, const RaySpan<T>& rays);
  void merge(const ErrorAccumulator& other);
  MethodErrors result() const;

 private:
  bool measureTMax_;
  LogHistogram angles_, laterals_;
  double angleMax_ = 0.0, lateralMax_ = 0.0, tMaxMax_ = 0.0;
  std::uint64_t nonfinite_ = 0, backward_ = 0, rays_ = 0, noRay_ = 0, noRayDisagree_ = 0;
};

extern template void ErrorAccumulator::addRow<float>(const std::vector<ReferenceRay>&,
                                                     const RaySpan<float>&);
extern template void ErrorAccumulator::addRow<double>(const std::vector<ReferenceRay>&,
                                                      const RaySpan<double>&);

// The angle between two reference rays of the same pixel (the exact ray of the float-rounded
// matrix against that of the double matrix: the float floor), in pixel angles of `exact`.
// Returns the row's maximum.
double floorAngleRowMax(const std::vector<ReferenceRay>& rounded,
                        const std::vector<ReferenceRay>& exact);
// The angle between each reference direction and that direction rounded to T, in pixel angles:
// what storing the exact ray in T already costs (the output floor). No method returning a T
// direction beats it on every pixel; for float it is about u_float = 2^-24 rad at worst, which
// exceeds the matrix floor where the float entries happen to be (nearly) exact. Row maximum.
template <typename T>
double outputFloorAngleRowMax(const std::vector<ReferenceRay>& reference);
extern template double outputFloorAngleRowMax<float>(const std::vector<ReferenceRay>&);
extern template double outputFloorAngleRowMax<double>(const std::vector<ReferenceRay>&);

// The origin's counterparts, in pixel footprints on the near plane (lateral distance from the
// exact ray line, as the origin error is measured): the float-rounded matrix's exact origin
// against the double matrix's ray (the matrix floor), and the exact origin rounded to T (the
// output floor: far from the origin, float spacing alone puts a stored origin pixels off).
double floorOriginRowMax(const std::vector<ReferenceRay>& rounded,
                         const std::vector<ReferenceRay>& exact);
template <typename T>
double outputFloorOriginRowMax(const std::vector<ReferenceRay>& reference);
extern template double outputFloorOriginRowMax<float>(const std::vector<ReferenceRay>&);
extern template double outputFloorOriginRowMax<double>(const std::vector<ReferenceRay>&);

// The angle between a computed unit direction and the reference's, in radians, accurate to well
// below 1e-20 rad near zero (the difference is taken against the double-double reference).
double angleToReference(const glm::dvec3& direction, const ReferenceRay& reference);
// Distance of `origin` from the reference ray's line.
double lateralDistanceToReference(const glm::dvec3& origin, const ReferenceRay& reference);

}  // namespace clipray

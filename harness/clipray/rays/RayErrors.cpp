#include "clipray/rays/RayErrors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clipray {

void LogHistogram::add(double value) {
  ++count_;
  if (!(value > 0.0)) {
    ++zeros_;
    return;
  }
  const double position = (std::log10(value) - kMinDecade) * kBinsPerDecade;
  const int bin = static_cast<int>(std::clamp(position, 0.0, double(bins_.size() - 1)));
  ++bins_[static_cast<std::size_t>(bin)];
}

void LogHistogram::merge(const LogHistogram& other) {
  for (std::size_t b = 0; b < bins_.size(); ++b) bins_[b] += other.bins_[b];
  zeros_ += other.zeros_;
  count_ += other.count_;
}

double LogHistogram::median() const {
  if (count_ == 0) return 0.0;
  const std::uint64_t half = (count_ + 1) / 2;
  if (zeros_ >= half) return 0.0;
  std::uint64_t seen = zeros_;
  for (std::size_t b = 0; b < bins_.size(); ++b) {
    seen += bins_[b];
    if (seen >= half) {
      // The geometric centre of the bin.
      return std::pow(10.0, kMinDecade + (static_cast<double>(b) + 0.5) / kBinsPerDecade);
    }
  }
  return std::numeric_limits<double>::infinity();
}

namespace {

glm::dvec3 hi(const DoubleDouble (&v)[3]) {
  return {v[0].hi, v[1].hi, v[2].hi};
}

// (a - hi) - lo per component: exact subtraction when a is near hi (Sterbenz), so the difference
// keeps the reference's extra bits.
glm::dvec3 difference(const glm::dvec3& a, const DoubleDouble (&v)[3]) {
  return {(a.x - v[0].hi) - v[0].lo, (a.y - v[1].hi) - v[1].lo, (a.z - v[2].hi) - v[2].lo};
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

double angleToReference(const glm::dvec3& direction, const ReferenceRay& reference) {
  const glm::dvec3 r = hi(reference.direction);
  const double cosine = glm::dot(direction, r);
  const double length = glm::length(direction);
  if (cosine > 0.5 * length) {
    // Small angles: the part of (d - r) across r is |d| sin(angle).
    const glm::dvec3 delta = difference(direction, reference.direction);
    const glm::dvec3 across = delta - glm::dot(delta, r) * r;
    return std::asin(std::min(1.0, glm::length(across) / length));
  }
  return std::atan2(glm::length(glm::cross(direction, r)), cosine);
}

double lateralDistanceToReference(const glm::dvec3& origin, const ReferenceRay& reference) {
  const glm::dvec3 r = hi(reference.direction);
  const glm::dvec3 delta = difference(origin, reference.origin);
  return glm::length(delta - glm::dot(delta, r) * r);
}

template <typename T>
void ErrorAccumulator::addRow(const std::vector<ReferenceRay>& reference, const RaySpan<T>& rays) {
  const int count = std::min(rays.count, static_cast<int>(reference.size()));
  for (int i = 0; i < count; ++i) {
    const ReferenceRay& ref = reference[static_cast<std::size_t>(i)];
    const CameraRay<T> ray = rays.load(i);
    const glm::dvec3 direction(ray.direction), origin(ray.origin);
    const double tMax = static_cast<double>(ray.tMax);
    // A method says "no ray" with a negative t_max (robust: kNoRayTMax).
    const bool methodRay = !(tMax < 0.0);
    if (!ref.hasRay()) {
      ++noRay_;
      if (methodRay) ++noRayDisagree_;
      continue;
    }
    if (!methodRay) {
      ++noRayDisagree_;
      continue;
    }
    ++rays_;
    const bool directionFinite = finite(direction);
    const bool originFinite = finite(origin);
    if (!directionFinite || !originFinite || std::isnan(tMax)) ++nonfinite_;
    if (directionFinite) {
      if (glm::dot(direction, hi(ref.direction)) < 0.0) ++backward_;
      const double angle = angleToReference(direction, ref) / ref.pixelAngle;
      angles_.add(angle);
      angleMax_ = std::max(angleMax_, angle);
    }
    if (originFinite) {
      const double lateral = lateralDistanceToReference(origin, ref) / ref.pixelFootprint;
      laterals_.add(lateral);
      lateralMax_ = std::max(lateralMax_, lateral);
    }
    if (measureTMax_) {
      double relative;
      if (std::isinf(ref.tMax)) {
        relative = tMax == ref.tMax ? 0.0 : std::numeric_limits<double>::infinity();
      } else if (std::isnan(tMax)) {
        relative = std::numeric_limits<double>::infinity();
      } else {
        relative = std::abs(tMax - ref.tMax) / ref.tMax;
      }
      tMaxMax_ = std::max(tMaxMax_, relative);
    }
  }
}

template void ErrorAccumulator::addRow<float>(const std::vector<ReferenceRay>&,
                                              const RaySpan<float>&);
template void ErrorAccumulator::addRow<double>(const std::vector<ReferenceRay>&,
                                               const RaySpan<double>&);

void ErrorAccumulator::merge(const ErrorAccumulator& other) {
  angles_.merge(other.angles_);
  laterals_.merge(other.laterals_);
  angleMax_ = std::max(angleMax_, other.angleMax_);
  lateralMax_ = std::max(lateralMax_, other.lateralMax_);
  tMaxMax_ = std::max(tMaxMax_, other.tMaxMax_);
  nonfinite_ += other.nonfinite_;
  backward_ += other.backward_;
  rays_ += other.rays_;
  noRay_ += other.noRay_;
  noRayDisagree_ += other.noRayDisagree_;
}

MethodErrors ErrorAccumulator::result() const {
  MethodErrors errors;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  errors.anglePx = {angles_.count() ? angleMax_ : nan, angles_.count() ? angles_.median() : nan};
  errors.originLateralPx = {laterals_.count() ? lateralMax_ : nan,
                            laterals_.count() ? laterals_.median() : nan};
  errors.tMaxRelativeMax = measureTMax_ ? tMaxMax_ : nan;
  errors.nonfinite = nonfinite_;
  errors.backward = backward_;
  errors.rays = rays_;
  errors.noRay = noRay_;
  errors.noRayDisagree = noRayDisagree_;
  return errors;
}

double floorAngleRowMax(const std::vector<ReferenceRay>& rounded,
                        const std::vector<ReferenceRay>& exact) {
  double worst = 0.0;
  const std::size_t count = std::min(rounded.size(), exact.size());
  for (std::size_t i = 0; i < count; ++i) {
    if (!rounded[i].hasRay() || !exact[i].hasRay()) continue;
    // The rounded reference as double-double: hi + lo carries ~106 bits, plenty for ~1e-8 rad.
    const glm::dvec3 direction(rounded[i].direction[0].hi + rounded[i].direction[0].lo,
                               rounded[i].direction[1].hi + rounded[i].direction[1].lo,
                               rounded[i].direction[2].hi + rounded[i].direction[2].lo);
    worst = std::max(worst, angleToReference(direction, exact[i]) / exact[i].pixelAngle);
  }
  return worst;
}

template <typename T>
double outputFloorAngleRowMax(const std::vector<ReferenceRay>& reference) {
  double worst = 0.0;
  for (const ReferenceRay& ray : reference) {
    if (!ray.hasRay()) continue;
    // hi rounded to T is the correctly rounded hi + lo except at exact ties (lo tips them):
    // a difference far below what is measured here.
    const glm::dvec3 stored(static_cast<T>(ray.direction[0].hi),
                            static_cast<T>(ray.direction[1].hi),
                            static_cast<T>(ray.direction[2].hi));
    worst = std::max(worst, angleToReference(stored, ray) / ray.pixelAngle);
  }
  return worst;
}

template double outputFloorAngleRowMax<float>(const std::vector<ReferenceRay>&);
template double outputFloorAngleRowMax<double>(const std::vector<ReferenceRay>&);

double floorOriginRowMax(const std::vector<ReferenceRay>& rounded,
                         const std::vector<ReferenceRay>& exact) {
  double worst = 0.0;
  const std::size_t count = std::min(rounded.size(), exact.size());
  for (std::size_t i = 0; i < count; ++i) {
    if (!rounded[i].hasRay() || !exact[i].hasRay()) continue;
    const glm::dvec3 origin(rounded[i].origin[0].hi + rounded[i].origin[0].lo,
                            rounded[i].origin[1].hi + rounded[i].origin[1].lo,
                            rounded[i].origin[2].hi + rounded[i].origin[2].lo);
    worst = std::max(worst, lateralDistanceToReference(origin, exact[i]) / exact[i].pixelFootprint);
  }
  return worst;
}

template <typename T>
double outputFloorOriginRowMax(const std::vector<ReferenceRay>& reference) {
  double worst = 0.0;
  for (const ReferenceRay& ray : reference) {
    if (!ray.hasRay()) continue;
    const glm::dvec3 stored(static_cast<T>(ray.origin[0].hi), static_cast<T>(ray.origin[1].hi),
                            static_cast<T>(ray.origin[2].hi));
    worst = std::max(worst, lateralDistanceToReference(stored, ray) / ray.pixelFootprint);
  }
  return worst;
}

template double outputFloorOriginRowMax<float>(const std::vector<ReferenceRay>&);
template double outputFloorOriginRowMax<double>(const std::vector<ReferenceRay>&);

}  // namespace clipray

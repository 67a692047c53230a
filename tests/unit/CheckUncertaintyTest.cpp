// The "+-" `clipray check` states against a Monte Carlo of the constructions it models: cameras
// built in float32 arithmetic as the engines of tests/support/engines/ build them (glm-style P * V
// in float; three.js and Filament in double, uploaded as float32), at random orientations, with
// the eye 1 to 1e5 from the origin, uploaded as exact float32 or listed with %g (the entries then
// moved within their six-digit rounding). Every reading is compared with the exact value of the
// typed planes. The stated bound must cover at least 99.9% of the readings and be at most 4x their
// spread (the largest deviation of a configuration's readings from the exact value). Fixed seed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "clipray/check/ConventionCheck.hpp"
#include "support/EngineCameras.hpp"

namespace clipray {
namespace {

namespace e = testing::engines;
constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Deterministic on every standard library: a 64-bit LCG (Knuth's MMIX constants), top 53 bits.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  double uniform(double lo, double hi) {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * static_cast<double>(state_ >> 11) * 0x1.0p-53;
  }
  glm::dvec3 direction() {
    for (;;) {
      const glm::dvec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const double l = glm::length(v);
      if (l > 0.1 && l <= 1.0) return v / l;
    }
  }

 private:
  std::uint64_t state_;
};

struct Build {
  const char* name;
  const char* builtFor;           // "no", "zo", "zo-reversed", "no-reversed"
  bool infinite = false;          // the far plane is at infinity whatever is typed
  bool doubleArithmetic = false;  // computed in double, uploaded as float32
};

const Build kBuilds[] = {
    {"glm perspectiveRH_NO", "no", false},
    {"glm perspectiveLH_ZO", "zo", false},
    {"three.js WebGL", "no", false, true},
    {"three.js WebGPU", "zo", false, true},
    {"three.js reversedDepth", "zo-reversed", false, true},
    {"godot set_perspective", "no", false},
    {"godot RD (reversed, y flip)", "zo-reversed", false},
    {"godot GL compatibility", "no-reversed", false},
    {"bgfx mtxProj NO", "no", false},
    {"bgfx mtxProj ZO", "zo", false},
    {"bgfx mtxProjInf reversed", "zo-reversed", true},
    {"filament", "zo-reversed", true, true},
    {"directxmath LH", "zo", false},
    {"directxmath RH", "zo", false},
    {"raylib", "no", false},
};

template <class T>
e::Vec3T<T> vec(const glm::dvec3& v) {
  return {static_cast<T>(v.x), static_cast<T>(v.y), static_cast<T>(v.z)};
}

// The camera of build b, as uploaded (float32 values, column-major).
e::Mat4 buildCamera(int b, const glm::dvec3& eye, const glm::dvec3& target, double near,
                    double far) {
  using F = float;
  const double fovDegrees = 60.0, aspect = 16.0 / 9.0;
  const F fov = static_cast<F>(fovDegrees * kPi / 180), fa = static_cast<F>(aspect);
  const F n = static_cast<F>(near), f = static_cast<F>(far);
  const auto product = [](const e::Mat4& p, const e::Mat4& v) {
    return e::toMat4(e::multiplyT<F>(e::fromMat4<F>(p), e::fromMat4<F>(v)));
  };
  switch (b) {
    case 0:
    case 1: {
      const e::Mat4 p = b == 0 ? e::glmx::perspectiveRH_NO<F>(fov, fa, n, f)
                               : e::glmx::perspectiveLH_ZO<F>(fov, fa, n, f);
      const e::Mat4 v = b == 0 ? e::glmx::lookAtRH<F>(vec<F>(eye), vec<F>(target), {0, 1, 0})
                               : e::glmx::lookAtLH<F>(vec<F>(eye), vec<F>(target), {0, 1, 0});
      return e::glmx::clipFromWorld<F>(p, v);
    }
    case 2:
    case 3:
    case 4: {
      const e::Mat4 p = e::threejs::perspectiveCamera<double>(
          fovDegrees, aspect, near, far,
          b == 3 ? e::threejs::CoordinateSystem::WebGPU : e::threejs::CoordinateSystem::WebGL,
          b == 4);
      const e::Mat4 v =
          e::threejs::viewFromLookAt<double>(vec<double>(eye), vec<double>(target), {0, 1, 0});
      return e::roundToFloat32(e::multiply(p, v));
    }
    case 5:
    case 6:
    case 7: {
      const e::Mat4 projection = e::godot::setPerspective<F>(static_cast<F>(fovDegrees), fa, n, f);
      const e::Mat4 p = b == 5   ? projection
                        : b == 6 ? e::godot::rdClipFromView<F>(projection, true)
                                 : e::godot::glesClipFromView<F>(projection, false);
      return product(p, e::godot::viewLookingAt<F>(vec<F>(eye), vec<F>(target), {0, 1, 0}));
    }
    case 8:
    case 9:
    case 10: {
      const e::Mat4 p = b == 10
                            ? e::bgfx::mtxProjInf<F>(static_cast<F>(fovDegrees), fa, n, false,
                                                     e::Handedness::Left, e::bgfx::NearFar::Reverse)
                            : e::bgfx::mtxProj<F>(static_cast<F>(fovDegrees), fa, n, f, b == 8);
      return product(p, e::bgfx::mtxLookAt<F>(vec<F>(eye), vec<F>(target)));
    }
    case 11: {
      const e::Mat4 p = e::filament::projectionForShaders<double>(
          e::filament::userPerspectiveFov<double>(fovDegrees, aspect, near, far));
      const e::Mat4 v =
          e::filament::viewFromLookAt<double>(vec<double>(eye), vec<double>(target), {0, 1, 0});
      return e::roundToFloat32(e::multiply(p, v));
    }
    case 12:
    case 13: {
      const auto p = b == 12 ? e::dxmath::perspectiveFovLH<F>(fov, fa, n, f)
                             : e::dxmath::perspectiveFovRH<F>(fov, fa, n, f);
      const auto v = b == 12 ? e::dxmath::lookAtLH<F>(vec<F>(eye), vec<F>(target), {0, 1, 0})
                             : e::dxmath::lookAtRH<F>(vec<F>(eye), vec<F>(target), {0, 1, 0});
      return e::dxmath::memoryOrder(e::dxmath::multiply(v, p));
    }
    default: {
      const e::Mat4 p = e::raylib::matrixPerspective<F>(fovDegrees * kPi / 180, aspect, near, far);
      return product(p, e::raylib::matrixLookAt<F>(vec<F>(eye), vec<F>(target), {0, 1, 0}));
    }
  }
}

glm::dmat4 toGlm(const e::Mat4& m, bool asSixDigits) {
  glm::dmat4 out;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      out[c][r] = m[static_cast<std::size_t>(4 * c + r)];
      if (asSixDigits) {
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%g", out[c][r]);
        out[c][r] = std::strtod(buffer, nullptr);
      }
    }
  }
  return out;
}

// The readings of one configuration (build, planes, eye distance, listing) for one quantity.
struct Sample {
  double deviation = 0.0;  // reading - exact
  double bound = 0.0;      // the stated +-
};

struct Quantity {
  std::vector<Sample> samples;
  int unread = 0;  // no reading stated (the precision cannot place the plane)
};

struct Summary {
  long samples = 0, covered = 0;
  double worstRatio = 0.0, bestRatio = kInf;
  std::string worstRatioAt, bestRatioAt;
  std::vector<std::string> uncovered;
};

// A configuration's readings: covered where |deviation| <= the stated bound; the bound's ratio to
// the spread is 1 / max(|deviation| / bound) (the stated bound over the largest deviation, each
// reading against its own bound, which varies with the orientation and the listed digits).
void summarize(const std::string& where, const Quantity& q, Summary& summary,
               std::vector<std::string>& table) {
  if (q.samples.empty()) return;
  double largest = 0.0, squares = 0.0, worstShare = 0.0;
  std::vector<double> bounds;
  for (const Sample& s : q.samples) {
    ++summary.samples;
    if (std::abs(s.deviation) <= s.bound) {
      ++summary.covered;
    } else if (summary.uncovered.size() < 10) {
      char line[200];
      std::snprintf(line, sizeof line, "%s: deviation %.3g beyond the stated %.3g", where.c_str(),
                    s.deviation, s.bound);
      summary.uncovered.push_back(line);
    }
    largest = std::max(largest, std::abs(s.deviation));
    squares += s.deviation * s.deviation;
    worstShare = std::max(worstShare, std::abs(s.deviation) / s.bound);
    bounds.push_back(s.bound);
  }
  std::sort(bounds.begin(), bounds.end());
  const double median = bounds[bounds.size() / 2];
  const double sd = std::sqrt(squares / static_cast<double>(q.samples.size()));
  // A spread of zero (every reading exact) has no ratio.
  const double ratio = worstShare > 0.0 ? 1.0 / worstShare : 0.0;
  if (worstShare > 0.0 && ratio > summary.worstRatio) {
    summary.worstRatio = ratio;
    summary.worstRatioAt = where;
  }
  if (worstShare > 0.0 && ratio < summary.bestRatio) {
    summary.bestRatio = ratio;
    summary.bestRatioAt = where;
  }
  char line[240];
  std::snprintf(line, sizeof line, "%-58s sd %9.3g max %9.3g bound %9.3g  x%5.2f (x%5.2f sd)",
                where.c_str(), sd, largest, median, ratio, sd > 0 ? median / sd : 0.0);
  table.push_back(line);
}

TEST(CheckUncertainty, StatedBoundsCoverFloat32ConstructionsAndStayTight) {
  Random random(0x0c0ffee42u);
  const double eyeDistances[] = {1.0, 10.0, 222.0, 1e3, 1e4, 1e5};
  constexpr int kPerConfiguration = 150;
  Summary summary;
  std::vector<std::string> table;
  std::map<std::string, Summary> byQuantity;
  for (int b = 0; b < static_cast<int>(std::size(kBuilds)); ++b) {
    const Build& build = kBuilds[b];
    const std::string builtFor = build.builtFor;
    const bool reversed = builtFor.find("reversed") != std::string::npos;
    const bool zo = builtFor.starts_with("zo");
    for (const double distance : eyeDistances) {
      for (const bool sixDigits : {false, true}) {
        std::map<std::string, Quantity> quantities;
        for (int k = 0; k < kPerConfiguration; ++k) {
          // The typed planes: the projection's own roundings are sampled too.
          const double n = std::exp(random.uniform(std::log(0.05), std::log(2.0)));
          const double typedFar = n * std::exp(random.uniform(std::log(20.0), std::log(1e4)));
          const double f = build.infinite ? kInf : typedFar;
          const double exactNo = zo ? (std::isfinite(f) ? f * n / (2 * f - n) : n / 2) : n;
          const double exactZo = zo ? n : (std::isfinite(f) ? 2 * f * n / (f + n) : 2 * n);
          const glm::dvec3 eye = random.direction() * distance;
          glm::dvec3 forward;
          do {
            forward = random.direction();
          } while (std::abs(forward.y) > 0.95);
          const glm::dvec3 target =
              eye + forward * std::max(random.uniform(1.0, 100.0), distance * 1e-3);
          CheckInput input;
          input.predictMethods = false;
          input.clipFromWorld = toGlm(buildCamera(b, eye, target, n, typedFar), sixDigits);
          input.declaredDepth = zo ? DepthConvention::ZeroToOne : DepthConvention::NegativeOneToOne;
          input.declaredReversed = reversed;
          input.origin = WindowOrigin::UpperLeft;
          // three.js and Filament compute in double and upload float32: the app says so.
          if (build.doubleArithmetic) input.precision = EntryPrecision::Arithmetic::Double;
          const MatrixProperties p = checkConventions(input).properties;
          const auto take = [&](const char* name, const std::optional<Uncertain>& reading,
                                double exact) {
            Quantity& q = quantities[name];
            if (!reading) {
              ++q.unread;
              return;
            }
            q.samples.push_back({reading->value - exact, reading->error});
          };
          take("near", p.near, n);
          if (std::isfinite(f)) take("far", p.far, f);
          if (!reversed) {
            take("near if NO", p.nearIfBuiltForNo, exactNo);
            take("near if ZO", p.nearIfBuiltForZo, exactZo);
          }
        }
        for (const auto& [name, q] : quantities) {
          char where[160];
          std::snprintf(where, sizeof where, "%s |eye| %g%s: %s", build.name, distance,
                        sixDigits ? " %g" : "", name.c_str());
          summarize(where, q, summary, table);
          summarize(where, q, byQuantity[name], table);
          table.pop_back();
        }
      }
    }
  }
  for (const std::string& line : table) std::printf("%s\n", line.c_str());
  for (const auto& [name, s] : byQuantity) {
    std::printf("%-12s %7ld readings, %.4f%% covered, bound/spread from x%.2f (%s) to x%.2f (%s)\n",
                name.c_str(), s.samples,
                100.0 * static_cast<double>(s.covered) / static_cast<double>(s.samples),
                s.bestRatio, s.bestRatioAt.c_str(), s.worstRatio, s.worstRatioAt.c_str());
  }
  for (const std::string& line : summary.uncovered) std::printf("  %s\n", line.c_str());
  const double coverage =
      static_cast<double>(summary.covered) / static_cast<double>(summary.samples);
  std::printf("all: %ld readings, %.4f%% covered, bound/spread at most x%.2f (%s)\n",
              summary.samples, 100.0 * coverage, summary.worstRatio, summary.worstRatioAt.c_str());
  EXPECT_GE(coverage, 0.999);
  EXPECT_LE(summary.worstRatio, 4.0);
}

}  // namespace
}  // namespace clipray

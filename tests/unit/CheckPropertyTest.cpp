// `clipray check` on thousands of generated cameras: the formulas of seven engines
// (tests/support/engines/), random orientation, eye up to 1e7 from the origin, fov 0.01-170 deg,
// round and random clip planes, finite, infinite and reversed depth, off-axis, oblique, mirrored
// and y-flipped variants; float32 (exact, and as %.9g / %g text) and double; each checked under
// the conventions it is meant for and under injected mistakes. The properties must match the
// construction within the uncertainty the report states, and the errors must be exactly the
// mistakes injected where the matrix can tell them apart. Fixed seed; CLIPRAY_CHECK_CAMERAS=N
// runs a larger sample.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "clipray/check/ConventionCheck.hpp"
#include "support/EngineCameras.hpp"

namespace clipray {
namespace {

namespace e = testing::engines;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// Deterministic on every standard library: a 64-bit LCG (Knuth's MMIX constants), top 53 bits.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  double uniform(double lo, double hi) {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * static_cast<double>(state_ >> 11) * 0x1.0p-53;
  }
  double logUniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  int below(int n) { return std::min(n - 1, static_cast<int>(uniform(0.0, n))); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
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

// What a camera was built as: the properties `check` must read back.
struct Truth {
  bool perspective = true;
  std::string builtFor;  // "no", "zo" or "zo-reversed"
  bool reversed = false, infiniteFar = false, mirrored = false, yFlipped = false;
  bool offAxis = false, oblique = false;
  bool roundPlanes = false;                   // near and far typed as round numbers
  double near = 0.0, far = kInf, fovY = 0.0;  // fovY 0: not symmetric (not asserted)
  glm::dvec3 eye{0.0}, forward{0.0};
  double forwardSlack = 0.0;  // radians the float construction itself may turn the view by
  double unitRoundoff = 0.0;  // of the arithmetic the camera was built in
};

struct Camera {
  std::string engine, form;
  e::Mat4 clipFromWorld{};
  Truth truth;
};

glm::dmat4 toGlm(const e::Mat4& m) {
  glm::dmat4 out;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c][r] = m[static_cast<std::size_t>(4 * c + r)];
  return out;
}

// The matrix as an app logs it: printf format, parsed back.
glm::dmat4 asText(const glm::dmat4& m, const char* format) {
  glm::dmat4 out;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, format, m[c][r]);
      out[c][r] = std::strtod(buffer, nullptr);
    }
  }
  return out;
}

const double kRoundNears[] = {0.01, 0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 0.001, 0.3};
const double kRoundFars[] = {10.0, 50.0, 100.0, 500.0, 1000.0, 5000.0, 1e4};

struct Parameters {
  glm::dvec3 eye, target;
  double fovY, aspect, near, far;  // far may be kInf
  bool round;
};

Parameters drawParameters(Random& random, bool allowInfinite) {
  Parameters p;
  const double eyeDistance = random.logUniform(0.1, 1e7);
  p.eye = random.direction() * eyeDistance;
  glm::dvec3 forward;
  do {
    forward = random.direction();
  } while (std::abs(forward.y) > 0.95);
  // Far from the origin the target is placed far enough that float can still aim at it.
  p.target = p.eye + forward * std::max(random.logUniform(1.0, 100.0), eyeDistance * 1e-3);
  p.fovY = random.chance(0.1) ? random.logUniform(0.01, 1.0) : random.uniform(1.0, 170.0);
  p.aspect = random.uniform(0.5, 3.5);
  p.round = random.chance(0.6);
  if (p.round) {
    p.near = kRoundNears[random.below(9)];
    p.far = kRoundFars[random.below(7)];
    if (p.far < 20.0 * p.near) p.far = 1000.0;
  } else {
    p.near = random.logUniform(1e-3, 2.0);
    p.far = p.near * random.logUniform(20.0, 1e4);
  }
  if (allowInfinite && random.chance(0.2)) p.far = kInf;
  return p;
}

// The vertical fov a symmetric projection encodes (its y scale is cot(fov/2)): what the uploaded
// matrix holds, whatever trigonometry the engine approximated the typed fov with.
double fovOf(const e::Mat4& clipFromView) {
  return 2.0 * std::atan(1.0 / std::abs(clipFromView[5])) * 180.0 / kPi;
}

template <class T>
e::Vec3T<T> vec(const glm::dvec3& v) {
  return {static_cast<T>(v.x), static_cast<T>(v.y), static_cast<T>(v.z)};
}

Truth baseTruth(const Parameters& p, double unitRoundoff) {
  Truth t;
  t.roundPlanes = p.round;
  t.near = p.near;
  t.far = p.far;
  t.infiniteFar = !std::isfinite(p.far);
  t.fovY = p.fovY;
  t.eye = p.eye;
  t.forward = glm::normalize(p.target - p.eye);
  t.unitRoundoff = unitRoundoff;
  // Float aims from an eye |e| away with error ~u |e| per coordinate.
  t.forwardSlack = 16.0 * unitRoundoff * (1.0 + glm::length(p.eye) / glm::length(p.target - p.eye));
  return t;
}

// One camera of an engine, in arithmetic T; `variant` picks among the engine's builds.
template <class T>
Camera makeCamera(int engine, int variant, Random& random) {
  constexpr double u = std::is_same_v<T, float> ? 0x1.0p-24 : 0x1.0p-53;
  Camera camera;
  camera.form = std::is_same_v<T, float> ? "float32" : "double";
  const double rad = kPi / 180.0;
  switch (engine) {
    case 0: {  // glm: perspective / infinite / frustum (off-axis) / ortho, RH and LH, NO and ZO
      camera.engine = "glm";
      const bool lh = variant % 4 == 1, zo = variant % 2 == 1;
      Parameters p = drawParameters(random, true);
      Truth t = baseTruth(p, u);
      const T fov = static_cast<T>(p.fovY * rad), aspect = static_cast<T>(p.aspect);
      const T n = static_cast<T>(p.near), f = static_cast<T>(p.far);
      e::Mat4 projection;
      const int kind = variant / 4 % 4;  // 0 perspective, 1 frustum off-axis, 2 ortho, 3 same as 0
      if (kind == 1) {
        p.far = std::isfinite(p.far) ? p.far : 1000.0;
        t.far = p.far;
        t.infiniteFar = false;
        const double top = p.near * std::tan(p.fovY * rad / 2), right = top * p.aspect;
        const double shiftX = random.uniform(0.1, 0.6) * right * (random.chance(0.5) ? 1 : -1);
        const double shiftY = random.uniform(0.1, 0.6) * top * (random.chance(0.5) ? 1 : -1);
        const auto l = static_cast<T>(-right + shiftX), r = static_cast<T>(right + shiftX);
        const auto b = static_cast<T>(-top + shiftY), tp = static_cast<T>(top + shiftY);
        const auto ff = static_cast<T>(p.far);
        projection = lh ? (zo ? e::glmx::frustumLH_ZO<T>(l, r, b, tp, n, ff)
                              : e::glmx::frustumLH_NO<T>(l, r, b, tp, n, ff))
                        : (zo ? e::glmx::frustumRH_ZO<T>(l, r, b, tp, n, ff)
                              : e::glmx::frustumRH_NO<T>(l, r, b, tp, n, ff));
        t.offAxis = true;
        t.fovY = 0.0;
        camera.engine = "glm";
      } else if (kind == 2) {
        t.perspective = false;
        t.infiniteFar = false;
        p.far = std::isfinite(p.far) ? p.far : 1000.0;
        t.far = p.far;
        t.fovY = 0.0;
        const auto h = static_cast<T>(random.logUniform(0.1, 100.0));
        const auto w = static_cast<T>(static_cast<double>(h) * p.aspect);
        const auto ff = static_cast<T>(p.far);
        projection = lh ? (zo ? e::glmx::orthoLH_ZO<T>(-w, w, -h, h, n, ff)
                              : e::glmx::orthoLH_NO<T>(-w, w, -h, h, n, ff))
                        : (zo ? e::glmx::orthoRH_ZO<T>(-w, w, -h, h, n, ff)
                              : e::glmx::orthoRH_NO<T>(-w, w, -h, h, n, ff));
      } else if (!std::isfinite(p.far)) {
        projection = lh ? (zo ? e::glmx::infinitePerspectiveLH_ZO<T>(fov, aspect, n)
                              : e::glmx::infinitePerspectiveLH_NO<T>(fov, aspect, n))
                        : (zo ? e::glmx::infinitePerspectiveRH_ZO<T>(fov, aspect, n)
                              : e::glmx::infinitePerspectiveRH_NO<T>(fov, aspect, n));
      } else {
        projection = lh ? (zo ? e::glmx::perspectiveLH_ZO<T>(fov, aspect, n, f)
                              : e::glmx::perspectiveLH_NO<T>(fov, aspect, n, f))
                        : (zo ? e::glmx::perspectiveRH_ZO<T>(fov, aspect, n, f)
                              : e::glmx::perspectiveRH_NO<T>(fov, aspect, n, f));
      }
      const e::Mat4 view = lh ? e::glmx::lookAtLH<T>(vec<T>(p.eye), vec<T>(p.target), {0, 1, 0})
                              : e::glmx::lookAtRH<T>(vec<T>(p.eye), vec<T>(p.target), {0, 1, 0});
      camera.clipFromWorld = e::glmx::clipFromWorld<T>(projection, view);
      if (t.fovY > 0) t.fovY = fovOf(projection);
      t.builtFor = zo ? "zo" : "no";
      t.mirrored = lh;
      camera.truth = t;
      return camera;
    }
    case 1: {  // three.js: computed in double, uploaded as float32 (T picks the upload)
      camera.engine = "three.js";
      Parameters p = drawParameters(random, false);
      Truth t = baseTruth(p, u);
      const int kind = variant % 4;  // WebGL, WebGPU, reversedDepth, orthographic
      const auto system =
          kind == 1 ? e::threejs::CoordinateSystem::WebGPU : e::threejs::CoordinateSystem::WebGL;
      e::Mat4 projection;
      if (kind == 3) {
        t.perspective = false;
        t.fovY = 0.0;
        const double h = random.logUniform(0.1, 100.0), w = h * p.aspect;
        projection = e::threejs::orthographicCamera<double>(-w, w, h, -h, p.near, p.far);
        t.builtFor = "no";
      } else {
        const bool offset = random.chance(0.3);
        e::threejs::ViewOffset<double> view{
            1920, 1080, random.uniform(100, 600), random.uniform(100, 400), 1920, 1080};
        projection = e::threejs::perspectiveCamera<double>(
            p.fovY, p.aspect, p.near, p.far, system, kind == 2, 1.0, offset ? &view : nullptr);
        t.offAxis = offset;
        if (offset) t.fovY = 0.0;
        t.builtFor = kind == 0 ? "no" : kind == 1 ? "zo" : "zo-reversed";
        t.reversed = kind == 2;
      }
      const e::Mat4 view =
          e::threejs::viewFromLookAt<double>(vec<double>(p.eye), vec<double>(p.target), {0, 1, 0});
      camera.clipFromWorld = e::multiply(projection, view);
      if constexpr (std::is_same_v<T, float>) {
        camera.clipFromWorld = e::roundToFloat32(camera.clipFromWorld);
      }
      if (t.fovY > 0) t.fovY = fovOf(projection);
      camera.truth = t;
      return camera;
    }
    case 2: {  // Godot 4: Projection, uploaded by the RD (reversed ZO, y flipped) or GL renderer
      camera.engine = "godot";
      Parameters p = drawParameters(random, false);
      Truth t = baseTruth(p, u);
      const e::Mat4 projection =
          e::godot::setPerspective<T>(static_cast<T>(p.fovY), static_cast<T>(p.aspect),
                                      static_cast<T>(p.near), static_cast<T>(p.far));
      const int kind = variant % 3;  // plain NO (4.0-4.2 GL), RD, GL compatibility (reversed NO)
      e::Mat4 clipFromView = projection;
      t.builtFor = "no";
      if (kind == 1) {
        clipFromView = e::godot::rdClipFromView<T>(projection, true);
        t.builtFor = "zo-reversed";
        t.reversed = true;
        t.yFlipped = true;
      } else if (kind == 2) {
        clipFromView = e::godot::glesClipFromView<T>(projection, false);
        t.builtFor = "no-reversed";
        t.reversed = true;
      }
      const e::Mat4 view =
          e::godot::viewLookingAt<T>(vec<T>(p.eye), vec<T>(p.target), {T(0), T(1), T(0)});
      camera.clipFromWorld =
          e::toMat4(e::multiplyT<T>(e::fromMat4<T>(clipFromView), e::fromMat4<T>(view)));
      t.fovY = fovOf(clipFromView);
      camera.truth = t;
      return camera;
    }
    case 3: {  // bgfx / bx: LH by default, NO or ZO by homogeneousNdc, reversed infinite
      camera.engine = "bgfx";
      Parameters p = drawParameters(random, false);
      Truth t = baseTruth(p, u);
      const bool homogeneous = variant % 2 == 0;
      const bool reversedInfinite = variant % 3 == 2;
      e::Mat4 projection;
      if (reversedInfinite) {
        projection = e::bgfx::mtxProjInf<T>(static_cast<T>(p.fovY), static_cast<T>(p.aspect),
                                            static_cast<T>(p.near), false, e::Handedness::Left,
                                            e::bgfx::NearFar::Reverse);
        t.builtFor = "zo-reversed";
        t.reversed = true;
        t.infiniteFar = true;
        t.far = kInf;
      } else {
        projection =
            e::bgfx::mtxProj<T>(static_cast<T>(p.fovY), static_cast<T>(p.aspect),
                                static_cast<T>(p.near), static_cast<T>(p.far), homogeneous);
        t.builtFor = homogeneous ? "no" : "zo";
      }
      const e::Mat4 view = e::bgfx::mtxLookAt<T>(vec<T>(p.eye), vec<T>(p.target));
      camera.clipFromWorld =
          e::toMat4(e::multiplyT<T>(e::fromMat4<T>(projection), e::fromMat4<T>(view)));
      t.mirrored = true;  // left-handed
      t.fovY = fovOf(projection);
      camera.truth = t;
      return camera;
    }
    case 4: {  // Filament: double, reversed ZO with an infinite far plane, uploaded as float32
      camera.engine = "filament";
      Parameters p = drawParameters(random, false);
      Truth t = baseTruth(p, u);
      const e::Mat4 projection = e::filament::projectionForShaders<double>(
          e::filament::userPerspectiveFov<double>(p.fovY, p.aspect, p.near, p.far));
      const e::Mat4 view =
          e::filament::viewFromLookAt<double>(vec<double>(p.eye), vec<double>(p.target), {0, 1, 0});
      camera.clipFromWorld = e::multiply(projection, view);
      if constexpr (std::is_same_v<T, float>) {
        camera.clipFromWorld = e::roundToFloat32(camera.clipFromWorld);
      }
      t.builtFor = "zo-reversed";
      t.reversed = true;
      t.infiniteFar = true;
      t.far = kInf;
      t.fovY = fovOf(projection);
      camera.truth = t;
      return camera;
    }
    case 5: {  // DirectXMath: row vectors, ZO, LH or RH, the XMMATRIX memory order as uploaded
      camera.engine = "directxmath";
      Parameters p = drawParameters(random, false);
      Truth t = baseTruth(p, u);
      const bool lh = variant % 2 == 0;
      const T fov = static_cast<T>(p.fovY * rad), aspect = static_cast<T>(p.aspect);
      const T n = static_cast<T>(p.near), f = static_cast<T>(p.far);
      const auto projection = lh ? e::dxmath::perspectiveFovLH<T>(fov, aspect, n, f)
                                 : e::dxmath::perspectiveFovRH<T>(fov, aspect, n, f);
      const auto view = lh ? e::dxmath::lookAtLH<T>(vec<T>(p.eye), vec<T>(p.target), {0, 1, 0})
                           : e::dxmath::lookAtRH<T>(vec<T>(p.eye), vec<T>(p.target), {0, 1, 0});
      camera.clipFromWorld = e::dxmath::memoryOrder(e::dxmath::multiply(view, projection));
      t.builtFor = "zo";
      t.mirrored = lh;
      t.fovY = fovOf(e::dxmath::glColumnMajor(projection));
      camera.truth = t;
      return camera;
    }
    default: {  // raylib: MatrixPerspective (window in double, float formulas), NO, RH
      camera.engine = "raylib";
      Parameters p = drawParameters(random, false);
      Truth t = baseTruth(p, u);
      const e::Mat4 projection =
          e::raylib::matrixPerspective<T>(p.fovY * rad, p.aspect, p.near, p.far);
      const e::Mat4 view = e::raylib::matrixLookAt<T>(vec<T>(p.eye), vec<T>(p.target), {0, 1, 0});
      camera.clipFromWorld =
          e::toMat4(e::multiplyT<T>(e::fromMat4<T>(projection), e::fromMat4<T>(view)));
      t.builtFor = "no";
      t.fovY = fovOf(projection);
      camera.truth = t;
      return camera;
    }
  }
}

// Lengyel's oblique near plane on a glm RH camera: the water plane y = h below the eye, tilted
// against the view (a reflection camera's clip plane).
template <class T>
Camera makeObliqueCamera(Random& random, bool zo) {
  constexpr double u = std::is_same_v<T, float> ? 0x1.0p-24 : 0x1.0p-53;
  Parameters p = drawParameters(random, false);
  Truth t = baseTruth(p, u);
  const e::Mat4 projection = zo ? e::glmx::perspectiveRH_ZO<T>(
                                      static_cast<T>(p.fovY * kPi / 180), static_cast<T>(p.aspect),
                                      static_cast<T>(p.near), static_cast<T>(p.far))
                                : e::glmx::perspectiveRH_NO<T>(
                                      static_cast<T>(p.fovY * kPi / 180), static_cast<T>(p.aspect),
                                      static_cast<T>(p.near), static_cast<T>(p.far));
  const e::Mat4 view = e::glmx::lookAtRH<T>(vec<T>(p.eye), vec<T>(p.target), {0, 1, 0});
  // A plane in view space through a point q ahead of the eye, its normal n tilted 20-70 deg from
  // the view axis: C = (-n, n . q), with the eye on its negative side (Lengyel's convention: what
  // lies beyond the plane, C . p > 0, is kept).
  const double tilt = random.uniform(20.0, 70.0) * kPi / 180, spin = random.uniform(0, 2 * kPi);
  const glm::dvec3 normal(std::sin(tilt) * std::cos(spin), std::sin(tilt) * std::sin(spin),
                          std::cos(tilt));
  const glm::dvec3 point(0.0, 0.0, -p.near * random.uniform(1.5, 4.0));
  const e::Vec4 plane{-normal.x, -normal.y, -normal.z, glm::dot(normal, point)};
  const auto oblique = e::oblique::obliqueNearPlane(
      projection, plane, zo ? e::oblique::Depth::ZO : e::oblique::Depth::NO);
  Camera camera;
  camera.engine = "oblique";
  camera.form = std::is_same_v<T, float> ? "float32" : "double";
  camera.clipFromWorld = e::glmx::clipFromWorld<T>(*oblique, view);
  t.builtFor = zo ? "zo" : "no";
  t.oblique = true;
  t.infiniteFar = false;
  t.far = kInf;  // Lengyel's far plane is skewed: not asserted
  t.fovY = fovOf(projection);
  camera.truth = t;
  return camera;
}

struct Tally {
  std::map<std::string, int> cameras, checks, findings;
  int falseErrors = 0, missedErrors = 0, wrongProperties = 0, coincidences = 0;
  // Per engine: the other-convention mistakes injected, those the Monte Carlo criterion says
  // the entries decide (the other reading further than twice its stated bound from every round
  // number, the typed one within half the bound that makes roundness evidence), and those found.
  std::map<std::string, int> conventionMistakes, decidableMistakes, foundMistakes;
  int refusedAsSingular = 0;
  std::vector<std::string> failures;
  void fail(const std::string& what) {
    if (failures.size() < 25) failures.push_back(what);
  }
};

// The other convention's reading of a typed near plane n (far f): the same matrix read as built
// for the other convention.
double otherReading(const Truth& t) {
  const double n = t.near, f = t.far;
  if (t.builtFor == "no") return std::isfinite(f) ? 2 * f * n / (f + n) : 2 * n;
  return std::isfinite(f) ? f * n / (2 * f - n) : n / 2;
}

std::string describe(const Camera& camera, const std::string& mistake) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, "%s %s (%s) near %.9g far %.9g fov %.4g |eye| %.3g",
                camera.engine.c_str(), camera.form.c_str(), mistake.c_str(), camera.truth.near,
                camera.truth.far, camera.truth.fovY, glm::length(camera.truth.eye));
  return buffer;
}

void checkOne(const Camera& camera, const glm::dmat4& listed, const std::string& form,
              const std::string& mistake, Tally& tally) {
  const Truth& t = camera.truth;
  CheckInput input;
  input.predictMethods = false;
  input.clipFromWorld = listed;
  const bool zoBuilt = t.builtFor == "zo" || t.builtFor == "zo-reversed";
  input.declaredDepth = zoBuilt ? DepthConvention::ZeroToOne : DepthConvention::NegativeOneToOne;
  input.declaredReversed = t.reversed;
  input.origin = t.yFlipped ? WindowOrigin::UpperLeft : WindowOrigin::LowerLeft;
  std::set<std::string> injected;  // error codes the mistake should produce
  bool decidable = true;
  bool flippedByMistake = false;
  if (mistake == "other-convention") {
    input.declaredDepth = zoBuilt ? DepthConvention::NegativeOneToOne : DepthConvention::ZeroToOne;
    injected.insert("depth-convention-mismatch");
    // Decidable when the typed near is round and the other reading is not, at the precision
    // the entries carry: settled once the report states the other reading's bound (below).
    decidable = t.perspective && !t.oblique && t.roundPlanes && !t.reversed;
  } else if (mistake == "classic-depth-test") {
    input.declaredReversed = !t.reversed;
    injected.insert("reversed-z-mismatch");
  } else if (mistake == "transposed") {
    input.clipFromWorld = glm::transpose(listed);
    injected.insert("likely-transposed");
  } else if (mistake == "y-flip-lower-left") {
    input.clipFromWorld[0][1] *= -1;
    input.clipFromWorld[1][1] *= -1;
    input.clipFromWorld[2][1] *= -1;
    input.clipFromWorld[3][1] *= -1;
    input.origin = WindowOrigin::LowerLeft;
    flippedByMistake = true;
  }
  const std::string label = camera.engine + " " + form;
  ++tally.checks[camera.engine];
  // What the listed numbers can resolve, relative: the arithmetic's rounding over the terms of an
  // entry, plus a decimal listing's.
  const double listing = form.find("%g") != std::string::npos     ? 5e-6
                         : form.find("%.9g") != std::string::npos ? 5e-9
                                                                  : 0.0;
  const double resolution = 8 * t.unitRoundoff + listing;
  // The near plane is placed while the translation's rounding (|eye| resolution) is well below it.
  const bool nearResolved = glm::length(t.eye) * resolution < 0.01 * t.near;
  CheckReport report;
  try {
    report = checkConventions(input);
  } catch (const std::exception& error) {
    // A listing too coarse to place the near plane can make the depth row a copy of the w row:
    // then the matrix as given is singular, and saying so is right.
    if (!nearResolved && std::string(error.what()).find("singular") != std::string::npos) {
      ++tally.refusedAsSingular;
      return;
    }
    ++tally.wrongProperties;
    tally.fail(describe(camera, mistake) + " [" + form + "]: refused: " + error.what());
    return;
  }
  const MatrixProperties& p = report.properties;
  if (mistake == "other-convention") {
    // The Monte Carlo criterion (tests/unit/CheckUncertaintyTest.cpp validates the bound against
    // the readings' spread): the other reading's exact value lies further than twice its stated
    // bound from every round number. Twice: the reading itself is off its exact value by up to
    // the bound.
    // The typed reading is evidence of a typed plane while its bound is below 1/100 of the
    // spacing of two-digit numbers there (a random plane lands that close by chance less than
    // once in 50).
    const std::optional<Uncertain>& otherRead = zoBuilt ? p.nearIfBuiltForNo : p.nearIfBuiltForZo;
    const std::optional<Uncertain>& typedRead = zoBuilt ? p.nearIfBuiltForZo : p.nearIfBuiltForNo;
    const double exact = otherReading(t);
    const double spacing = std::pow(10.0, std::floor(std::log10(t.near)) - 1.0);
    decidable = decidable && otherRead && typedRead && typedRead->error < 0.5 * spacing / 100 &&
                std::abs(exact - nearestRoundNumber(exact)) > 2.0 * otherRead->error;
    ++tally.conventionMistakes[camera.engine];
    if (decidable) ++tally.decidableMistakes[camera.engine];
  }
  std::set<std::string> errors;
  for (const Finding& f : report.findings) {
    ++tally.findings[f.severity + ":" + f.code];
    if (f.severity == "error") errors.insert(f.code);
  }
  // A typed random plane whose other reading happens to be a round number is a different, equally
  // valid camera: the matrix cannot tell, and a reading of it is no false error.
  const std::optional<Uncertain>& other = zoBuilt ? p.nearIfBuiltForNo : p.nearIfBuiltForZo;
  const bool coincidence =
      !t.roundPlanes && t.perspective && !t.reversed && other &&
      significantDigits(otherReading(t), std::max(1e-9, 1.5 * other->error / other->value)) <= 2;
  for (const std::string& code : errors) {
    if (!injected.count(code)) {
      if (coincidence && code == "depth-convention-mismatch") {
        ++tally.coincidences;
        continue;
      }
      ++tally.falseErrors;
      char detail[160];
      std::snprintf(detail, sizeof detail, " NO %.9g +- %.3g, ZO %.9g +- %.3g",
                    p.nearIfBuiltForNo ? p.nearIfBuiltForNo->value : -1.0,
                    p.nearIfBuiltForNo ? p.nearIfBuiltForNo->error : -1.0,
                    p.nearIfBuiltForZo ? p.nearIfBuiltForZo->value : -1.0,
                    p.nearIfBuiltForZo ? p.nearIfBuiltForZo->error : -1.0);
      tally.fail(describe(camera, mistake) + " [" + form + "]: false error " + code +
                 " (built_for " + p.builtFor + ": " + p.builtForReason + ")" + detail);
    }
  }
  if (mistake == "other-convention" && errors.count("depth-convention-mismatch"))
    ++tally.foundMistakes[camera.engine];
  for (const std::string& code : injected) {
    if (decidable && !errors.count(code)) {
      ++tally.missedErrors;
      tally.fail(describe(camera, mistake) + " [" + form + "]: missed " + code + " (built_for " +
                 p.builtFor + ": " + p.builtForReason + ")");
    }
  }
  if (mistake == "transposed") return;  // the rest of the report describes the scrambled matrix

  // Properties.
  std::vector<std::string> wrong;
  const bool flipped = t.yFlipped || flippedByMistake;
  if (p.perspective != t.perspective) wrong.push_back("projection");
  if (p.reversed != t.reversed && t.perspective) wrong.push_back("reversed");
  if (p.leftHanded != t.mirrored) wrong.push_back("mirrored");
  if (p.yFlipped != flipped) wrong.push_back("y_flipped");
  if (p.oblique != t.oblique) wrong.push_back("oblique");
  if (t.perspective && p.offAxis != t.offAxis) wrong.push_back("off_axis");
  // A finite far plane shows as such while 2n/f clears the resolution of b = (f + n)/(f - n).
  const bool farResolved = t.infiniteFar || (nearResolved && 2 * t.near / t.far > 100 * resolution);
  if (t.perspective && !t.oblique && farResolved && p.infiniteFar != t.infiniteFar)
    wrong.push_back("infinite_far");
  if (t.perspective && !t.oblique && mistake.empty() && (p.near || nearResolved)) {
    // The near plane in force under the declared (right) convention is the typed one.
    if (!p.near ||
        std::abs(p.near->value - t.near) > 2 * p.near->error + 64 * t.unitRoundoff * t.near)
      wrong.push_back("near");
    if (!t.infiniteFar && p.far &&
        std::abs(p.far->value - t.far) > 2 * p.far->error + 64 * t.unitRoundoff * t.far)
      wrong.push_back("far");
    const bool declaredBuild =
        (t.builtFor == "no" || t.builtFor == "zo") ? p.builtFor == t.builtFor : true;
    // Any decision for the other convention is wrong, but for a typed random plane whose other
    // reading happens to be round (a different, equally valid camera).
    if (!t.reversed && !coincidence && !declaredBuild && p.builtFor != "ambiguous")
      wrong.push_back("built_for " + p.builtFor);
  }
  if (t.perspective && t.fovY > 0 && !t.oblique &&
      std::abs(p.fovYDegrees.value - t.fovY) > 2 * p.fovYDegrees.error + 1e-4 * t.fovY)
    wrong.push_back("fov_y");
  if (t.perspective && p.eye) {
    const glm::dvec3 slack =
        2.0 * p.eyeError + glm::dvec3(64 * t.unitRoundoff * glm::length(t.eye));
    const glm::dvec3 off = glm::abs(*p.eye - t.eye);
    if (off.x > slack.x || off.y > slack.y || off.z > slack.z) wrong.push_back("eye");
  }
  const double turn = std::atan2(glm::length(glm::cross(p.viewDirection, t.forward)),
                                 glm::dot(p.viewDirection, t.forward));
  if (turn > 2 * p.viewDirectionErrorDegrees * kPi / 180 + t.forwardSlack + 1e-12)
    wrong.push_back("view_direction");
  if (!wrong.empty()) {
    ++tally.wrongProperties;
    std::string list;
    for (const std::string& w : wrong) list += " " + w;
    char detail[256];
    std::snprintf(detail, sizeof detail,
                  " (far %.9g +- %.3g, near %.9g +- %.3g, NO %.9g +- %.3g, ZO %.9g +- %.3g)",
                  p.far ? p.far->value : -1.0, p.far ? p.far->error : -1.0,
                  p.near ? p.near->value : -1.0, p.near ? p.near->error : -1.0,
                  p.nearIfBuiltForNo ? p.nearIfBuiltForNo->value : -1.0,
                  p.nearIfBuiltForNo ? p.nearIfBuiltForNo->error : -1.0,
                  p.nearIfBuiltForZo ? p.nearIfBuiltForZo->value : -1.0,
                  p.nearIfBuiltForZo ? p.nearIfBuiltForZo->error : -1.0);
    std::string matrix;
    if (std::getenv("CLIPRAY_CHECK_DUMP")) {
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
          char number[40];
          std::snprintf(number, sizeof number, " %.17g", input.clipFromWorld[c][r]);
          matrix += number;
        }
    }
    tally.fail(describe(camera, mistake) + " [" + form + "]: wrong" + list + detail + matrix);
  }
}

TEST(CheckProperties, GeneratedCamerasOfEveryEngineReadAsBuilt) {
  const char* override = std::getenv("CLIPRAY_CHECK_CAMERAS");
  const int perEngine = override ? std::max(1, std::atoi(override)) : 680;
  Random random(0x5eed2026u);
  Tally tally;
  const auto run = [&](const Camera& camera, int index) {
    ++tally.cameras[camera.engine];
    const glm::dmat4 m = toGlm(camera.clipFromWorld);
    const bool isFloat = camera.form == "float32";
    // The right declaration in every form an app may hand the numbers over in.
    checkOne(camera, m, camera.form, "", tally);
    if (isFloat) checkOne(camera, asText(m, "%.9g"), "float32 as %.9g", "", tally);
    checkOne(camera, asText(m, "%g"), camera.form + " as %g", "", tally);
    // One mistake each, in turn.
    const Truth& t = camera.truth;
    switch (index % 4) {
      case 0:
        if (!t.reversed && !t.oblique) checkOne(camera, m, camera.form, "other-convention", tally);
        break;
      case 1:
        if (t.perspective && !t.oblique)
          checkOne(camera, m, camera.form, "classic-depth-test", tally);
        break;
      case 2:
        if (t.perspective && !t.oblique && !t.offAxis && glm::length(t.eye) > 1.0)
          checkOne(camera, m, camera.form, "transposed", tally);
        break;
      default:
        if (!t.mirrored && !t.yFlipped)
          checkOne(camera, m, camera.form, "y-flip-lower-left", tally);
        break;
    }
  };
  for (int engine = 0; engine < 7; ++engine) {
    for (int i = 0; i < perEngine; ++i) {
      run(i % 2 == 0 ? makeCamera<float>(engine, i / 2, random)
                     : makeCamera<double>(engine, i / 2, random),
          i);
    }
  }
  for (int i = 0; i < perEngine / 2; ++i) {
    run(i % 2 == 0 ? makeObliqueCamera<float>(random, i % 4 == 0)
                   : makeObliqueCamera<double>(random, i % 4 == 1),
        4 * i + 3);
  }
  int cameras = 0, checks = 0;
  std::printf("%-12s %8s %8s\n", "engine", "cameras", "checks");
  for (const auto& [engine, count] : tally.cameras) {
    std::printf("%-12s %8d %8d\n", engine.c_str(), count, tally.checks[engine]);
    cameras += count;
    checks += tally.checks[engine];
  }
  std::printf("%-12s %8d %8d\nfindings:\n", "all", cameras, checks);
  for (const auto& [code, count] : tally.findings)
    std::printf("  %-44s %6d\n", code.c_str(), count);
  std::printf(
      "false errors %d, missed decidable errors %d, wrong properties %d, coincidentally "
      "round other readings %d, listings too coarse for their camera (refused as singular) %d\n",
      tally.falseErrors, tally.missedErrors, tally.wrongProperties, tally.coincidences,
      tally.refusedAsSingular);
  std::printf("%-12s %10s %10s %10s\n", "engine", "NO/ZO", "decidable", "found");
  for (const auto& [engine, count] : tally.conventionMistakes) {
    std::printf("%-12s %10d %10d %10d\n", engine.c_str(), count, tally.decidableMistakes[engine],
                tally.foundMistakes[engine]);
  }
  for (const std::string& failure : tally.failures) std::printf("  %s\n", failure.c_str());
  EXPECT_GE(checks, 5000);
  EXPECT_EQ(tally.falseErrors, 0);
  EXPECT_EQ(tally.missedErrors, 0);
  EXPECT_EQ(tally.wrongProperties, 0);
}

}  // namespace
}  // namespace clipray

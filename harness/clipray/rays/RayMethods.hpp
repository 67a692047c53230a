#pragma once
// Every ray method of docs/bench.md, in float and double, behind one API: precompute once
// per camera and viewport (makeRayGenerator), then a scalar call per pixel (pixelRay) or a batch
// call per pixel row (generateRow, structure-of-arrays output). Each method takes the inputs its
// source takes (inverse_pv: separate projection and view; fov_tangent: scalars), rounded to the
// method's precision, so the comparison is honest. No method throws on the hot path.
// Matrices are column-major, p' = M * p: CameraInputs::clipFromWorld (built for its mode) =
// clipFromView * viewFromWorld; PerspectiveScalars::worldFromView is the camera's placement.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"

namespace clipray {

enum class RayMethod {
  UnprojectGlm,   // glm::unProjectNO/ZO of the near and far point, per pixel (what users do today)
  TwoPoint,       // worldFromClip once; near and far point; normalize(far - near) (seed 003, GLU)
  InversePv,      // viewFromClip * (x', y', z_n, 1), w := 0, then worldFromView (seeds 000/001)
  FovTangent,     // tan(fov/2), aspect, near/far scalars; perspective only (seed 003)
  PlaneCross,     // u = mx - x' mw, v = my - y' mw, d = u x v (seed 002 listing 2)
  PlaneCrossPre,  // d = x'(my x mw) + y'(mw x mx) + mx x my, 6 FMA (seed 002 listing 3)
  Full,           // origin + plane-cross direction + t_max + sign fix (seed 002 listing 4)
  Robust,         // ours (RobustRays.hpp)
};
inline constexpr std::array<RayMethod, 8> kRayMethods = {
    RayMethod::UnprojectGlm, RayMethod::TwoPoint,      RayMethod::InversePv, RayMethod::FovTangent,
    RayMethod::PlaneCross,   RayMethod::PlaneCrossPre, RayMethod::Full,      RayMethod::Robust};
std::string rayMethodName(RayMethod method);  // "unproject_glm", "two_point", ...
std::optional<RayMethod> parseRayMethod(std::string_view name);
// plane_cross and plane_cross_pre are direction methods: their sources give no t_max (theirs is
// +inf), so t_max errors are not reported for them.
bool methodProvidesTMax(RayMethod method);

enum class Precision { Float, Double };
inline constexpr std::array<Precision, 2> kPrecisions = {Precision::Float, Precision::Double};
std::string precisionName(Precision precision);  // "float", "double"

// Seed 003's inputs: a symmetric perspective camera described by scalars and its placement.
struct PerspectiveScalars {
  double fovYRadians = 0.0;
  double aspect = 1.0;  // width / height
  double nearDistance = 0.0;
  double farDistance = 0.0;  // +inf for an infinite far plane
  glm::dmat4 worldFromView{1.0};
};

// What a caller can hand the methods. clipFromWorld and mode are always there; the separated
// matrices and the scalars only where the camera was built from them.
struct CameraInputs {
  glm::dmat4 clipFromWorld{1.0};
  DepthMode mode;
  std::optional<glm::dmat4> clipFromView;         // with viewFromWorld: inverse_pv, unproject_glm
  std::optional<glm::dmat4> viewFromWorld;        // (clipFromWorld = clipFromView * viewFromWorld)
  std::optional<PerspectiveScalars> perspective;  // fov_tangent
};

// Empty when `method` can run on `inputs`; otherwise what it lacks, e.g. "needs fov/aspect
// scalars (a symmetric perspective camera)".
std::string missingInputs(RayMethod method, const CameraInputs& inputs);

template <typename T>
struct CameraRay {
  glm::vec<3, T> origin{T(0)};
  glm::vec<3, T> direction{T(0)};
  T tMax = T(0);
};

// Structure-of-arrays output of a batch call: `count` rays, one array per component.
template <typename T>
struct RaySpan {
  T* originX;
  T* originY;
  T* originZ;
  T* directionX;
  T* directionY;
  T* directionZ;
  T* tMax;
  int count;

  void store(int k, const CameraRay<T>& ray) const noexcept {
    originX[k] = ray.origin.x;
    originY[k] = ray.origin.y;
    originZ[k] = ray.origin.z;
    directionX[k] = ray.direction.x;
    directionY[k] = ray.direction.y;
    directionZ[k] = ray.direction.z;
    tMax[k] = ray.tMax;
  }
  CameraRay<T> load(int k) const noexcept {
    return {{originX[k], originY[k], originZ[k]},
            {directionX[k], directionY[k], directionZ[k]},
            tMax[k]};
  }
};

// Owns structure-of-arrays storage (32-byte aligned rows are not required: the kernels use
// unaligned stores).
template <typename T>
class RayBuffer {
 public:
  explicit RayBuffer(std::size_t count = 0) { resize(count); }
  void resize(std::size_t count) {
    for (auto& component : components_) component.assign(count, T(0));
  }
  std::size_t size() const { return components_[0].size(); }
  RaySpan<T> span(std::size_t offset, int count) {
    return {components_[0].data() + offset, components_[1].data() + offset,
            components_[2].data() + offset, components_[3].data() + offset,
            components_[4].data() + offset, components_[5].data() + offset,
            components_[6].data() + offset, count};
  }
  RaySpan<T> all() { return span(0, static_cast<int>(size())); }

 private:
  std::array<std::vector<T>, 7> components_;
};

// One method, one precision, one camera and viewport: everything per camera is precomputed.
template <typename T>
class RayGenerator {
 public:
  explicit RayGenerator(Viewport viewport) : viewport_(viewport) {}
  virtual ~RayGenerator() = default;
  // The ray through the centre of pixel (i, j), lower-left origin. Never throws.
  virtual CameraRay<T> pixelRay(int i, int j) const noexcept = 0;
  // The viewport.width rays of row j, written to out[0 .. width). Never throws. robust: the same
  // results as pixelRay, bit for bit; the other methods' batches are compiled for FMA when the
  // CPU has it and may differ from pixelRay by the rounding of contracted a * b + c.
  virtual void generateRow(int j, const RaySpan<T>& out) const noexcept = 0;
  Viewport viewport() const { return viewport_; }
  // Every row, bottom to top, into out (resized to width * height).
  void generateGrid(RayBuffer<T>& out) const;

 private:
  Viewport viewport_;
};

// nullptr when the method cannot run on these inputs (missingInputs says why).
template <typename T>
std::unique_ptr<RayGenerator<T>> makeRayGenerator(RayMethod method, const CameraInputs& inputs,
                                                  Viewport viewport);

extern template class RayGenerator<float>;
extern template class RayGenerator<double>;
extern template std::unique_ptr<RayGenerator<float>> makeRayGenerator<float>(RayMethod,
                                                                             const CameraInputs&,
                                                                             Viewport);
extern template std::unique_ptr<RayGenerator<double>> makeRayGenerator<double>(RayMethod,
                                                                               const CameraInputs&,
                                                                               Viewport);

// The batch code paths, slowest first. Every path gives robust's rays bit for bit (the same IEEE
// operations: FMA, sqrt, division and conversions are correctly rounded on all of them):
//   Portable  baseline x86-64 / other CPUs; FMA through libm, slow but the same numbers;
//   Avx2Fma   8 pixels per iteration, robust's double direction in two halves of 4 lanes;
//   Avx512    the same, the double direction in one register of 8 lanes (AVX-512F).
// Detected at run time with __builtin_cpu_supports; the kernels are built with
// __attribute__((target(...))), so one binary serves every x86-64 CPU.
enum class BatchCodePath { Portable, Avx2Fma, Avx512 };
std::string batchCodePathName(BatchCodePath path);  // "portable", "avx2+fma", "avx512f+avx2+fma"
// The paths this CPU can run, slowest first (Portable always).
std::vector<BatchCodePath> supportedBatchCodePaths();
// Generators made after this call use at most `limit` (tests pin every path against the scalar
// call; benchmarks compare them); std::nullopt restores the fastest. Not thread-safe with
// concurrent makeRayGenerator calls.
void limitBatchCodePath(std::optional<BatchCodePath> limit);
// The path a generator made now gets, by name.
std::string batchCodePath();

}  // namespace clipray

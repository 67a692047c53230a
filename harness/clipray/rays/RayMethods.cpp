#include "clipray/rays/RayMethods.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/ext/matrix_projection.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include "clipray/math/Projections.hpp"
#include "clipray/rays/RobustRayKernel.hpp"

#if defined(__x86_64__) || defined(__i386__)
#define CLIPRAY_X86 1
#else
#define CLIPRAY_X86 0
#endif

namespace clipray {

std::string rayMethodName(RayMethod method) {
  switch (method) {
    case RayMethod::UnprojectGlm:
      return "unproject_glm";
    case RayMethod::TwoPoint:
      return "two_point";
    case RayMethod::InversePv:
      return "inverse_pv";
    case RayMethod::FovTangent:
      return "fov_tangent";
    case RayMethod::PlaneCross:
      return "plane_cross";
    case RayMethod::PlaneCrossPre:
      return "plane_cross_pre";
    case RayMethod::Full:
      return "full";
    case RayMethod::Robust:
      return "robust";
  }
  return "?";
}

std::optional<RayMethod> parseRayMethod(std::string_view name) {
  for (const RayMethod method : kRayMethods) {
    if (rayMethodName(method) == name) return method;
  }
  return std::nullopt;
}

bool methodProvidesTMax(RayMethod method) {
  return method != RayMethod::PlaneCross && method != RayMethod::PlaneCrossPre;
}

std::string precisionName(Precision precision) {
  return precision == Precision::Float ? "float" : "double";
}

std::string missingInputs(RayMethod method, const CameraInputs& inputs) {
  if (method == RayMethod::InversePv && (!inputs.clipFromView || !inputs.viewFromWorld)) {
    return "needs the projection and view matrices separately";
  }
  if (method == RayMethod::FovTangent && !inputs.perspective) {
    return "needs fov/aspect/near/far scalars (a symmetric perspective camera)";
  }
  return {};
}

template <typename T>
void RayGenerator<T>::generateGrid(RayBuffer<T>& out) const {
  const int width = viewport_.width;
  out.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(viewport_.height));
  for (int j = 0; j < viewport_.height; ++j) {
    generateRow(j, out.span(static_cast<std::size_t>(j) * static_cast<std::size_t>(width), width));
  }
}

namespace {

constexpr bool kHaveX86 = CLIPRAY_X86 != 0;

bool cpuHasAvx2Fma() {
#if CLIPRAY_X86
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

bool cpuHasAvx512() {
#if CLIPRAY_X86
  static const bool has = cpuHasAvx2Fma() && __builtin_cpu_supports("avx512f");
  return has;
#else
  return false;
#endif
}

std::optional<BatchCodePath> batchCodePathLimit;

BatchCodePath activeBatchCodePath() {
  const BatchCodePath best = cpuHasAvx512()    ? BatchCodePath::Avx512
                             : cpuHasAvx2Fma() ? BatchCodePath::Avx2Fma
                                               : BatchCodePath::Portable;
  return batchCodePathLimit && *batchCodePathLimit < best ? *batchCodePathLimit : best;
}

template <typename T>
using Vec3 = glm::vec<3, T>;
template <typename T>
using Vec4 = glm::vec<4, T>;
template <typename T>
using Mat4 = glm::mat<4, 4, T>;

template <typename T>
T clipX(int i, int width) {
  return T(2 * i + 1) / T(width) - T(1);
}

template <typename T>
Vec3<T> dehomogenize(const Vec4<T>& p) {
  return Vec3<T>(p) / p.w;
}

template <typename T>
Vec3<T> fmaVec(T a, const Vec3<T>& b, const Vec3<T>& c) {
  return {std::fma(a, b.x, c.x), std::fma(a, b.y, c.y), std::fma(a, b.z, c.z)};
}

template <typename T>
Vec3<T> rowXyz(const Mat4<T>& m, int r) {
  return {m[0][r], m[1][r], m[2][r]};
}

// ---- The methods as their sources write them, each a small functor: ray(i, j). ----

// glm::unProjectNO/ZO twice per pixel; glm computes inverse(proj * model) inside every call.
template <typename T>
struct UnprojectGlmKernel {
  Mat4<T> model, projection;
  Vec4<T> viewportRect;
  T nearDepth, farDepth;  // window depth of the near and far plane (reversed-Z swaps them)
  bool zeroToOne;

  UnprojectGlmKernel(const CameraInputs& in, Viewport viewport)
      : model(in.viewFromWorld ? Mat4<T>(*in.viewFromWorld) : Mat4<T>(T(1))),
        projection(in.clipFromView ? Mat4<T>(*in.clipFromView) : Mat4<T>(in.clipFromWorld)),
        viewportRect(T(0), T(0), T(viewport.width), T(viewport.height)),
        nearDepth(in.mode.reversed ? T(1) : T(0)),
        farDepth(in.mode.reversed ? T(0) : T(1)),
        zeroToOne(in.mode.convention == DepthConvention::ZeroToOne) {}

  CameraRay<T> operator()(int i, int j) const {
    const Vec3<T> nearWin(T(i) + T(0.5), T(j) + T(0.5), nearDepth);
    const Vec3<T> farWin(T(i) + T(0.5), T(j) + T(0.5), farDepth);
    const Vec3<T> a = zeroToOne ? glm::unProjectZO(nearWin, model, projection, viewportRect)
                                : glm::unProjectNO(nearWin, model, projection, viewportRect);
    const Vec3<T> b = zeroToOne ? glm::unProjectZO(farWin, model, projection, viewportRect)
                                : glm::unProjectNO(farWin, model, projection, viewportRect);
    const Vec3<T> delta = b - a;
    const T length = glm::length(delta);
    return {a, delta / length, length};
  }
};

// worldFromClip once (in T, as a float app would); near and far point; normalize(far - near).
template <typename T>
struct TwoPointKernel {
  Mat4<T> worldFromClip;
  T zNear, zFar;
  int width, height;

  TwoPointKernel(const CameraInputs& in, Viewport viewport)
      : worldFromClip(glm::inverse(Mat4<T>(in.clipFromWorld))),
        zNear(T(in.mode.nearNdcZ())),
        zFar(T(in.mode.farNdcZ())),
        width(viewport.width),
        height(viewport.height) {}

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> a = dehomogenize(worldFromClip * Vec4<T>(x, y, zNear, T(1)));
    const Vec3<T> b = dehomogenize(worldFromClip * Vec4<T>(x, y, zFar, T(1)));
    const Vec3<T> delta = b - a;
    const T length = glm::length(delta);
    return {a, delta / length, length};
  }
};

// Seeds 000/001: viewFromClip * (x', y', z_n, 1), w := 0, then worldFromView. The origin is the
// near point through the same two inverses, t_max the distance to the far point.
template <typename T>
struct InversePvKernel {
  Mat4<T> viewFromClip, worldFromView;
  T zNear, zFar;
  int width, height;

  InversePvKernel(const CameraInputs& in, Viewport viewport)
      : viewFromClip(glm::inverse(Mat4<T>(*in.clipFromView))),
        worldFromView(glm::inverse(Mat4<T>(*in.viewFromWorld))),
        zNear(T(in.mode.nearNdcZ())),
        zFar(T(in.mode.farNdcZ())),
        width(viewport.width),
        height(viewport.height) {}

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec4<T> nearView = viewFromClip * Vec4<T>(x, y, zNear, T(1));
    const Vec3<T> direction =
        glm::normalize(Vec3<T>(worldFromView * Vec4<T>(Vec3<T>(nearView), T(0))));
    const Vec3<T> origin = Vec3<T>(worldFromView * Vec4<T>(dehomogenize(nearView), T(1)));
    const Vec4<T> farView = viewFromClip * Vec4<T>(x, y, zFar, T(1));
    const Vec3<T> farPoint = Vec3<T>(worldFromView * Vec4<T>(dehomogenize(farView), T(1)));
    return {origin, direction, glm::length(farPoint - origin)};
  }
};

// Seed 003: slopes from tan(fov / 2) and the aspect, in view space, rotated to world space by the
// inverse view matrix; origin on the near plane, t_max to the far plane.
template <typename T>
struct FovTangentKernel {
  T slopeX, slopeY, nearDistance, depth;
  Mat4<T> worldFromView;
  int width, height;

  FovTangentKernel(const CameraInputs& in, Viewport viewport)
      : worldFromView(Mat4<T>(in.perspective->worldFromView)),
        width(viewport.width),
        height(viewport.height) {
    const PerspectiveScalars& s = *in.perspective;
    const T tangent = std::tan(T(s.fovYRadians) * T(0.5));
    slopeX = tangent * T(s.aspect);
    slopeY = tangent;
    nearDistance = T(s.nearDistance);
    depth = T(s.farDistance) - T(s.nearDistance);  // +inf for an infinite far plane
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> slope = Vec3<T>(worldFromView * Vec4<T>(x * slopeX, y * slopeY, T(-1), T(0)));
    const Vec3<T> eye(worldFromView[3]);
    const T length = glm::length(slope);
    return {eye + nearDistance * slope, slope / length, depth * length};
  }
};

// Listing 1's origin (near point through worldFromClip), shared by the two direction listings.
template <typename T>
struct ListingOneOrigin {
  Mat4<T> worldFromClip;
  T zNear;
  explicit ListingOneOrigin(const CameraInputs& in)
      : worldFromClip(glm::inverse(Mat4<T>(in.clipFromWorld))), zNear(T(in.mode.nearNdcZ())) {}
  Vec3<T> operator()(T x, T y) const {
    return dehomogenize(worldFromClip * Vec4<T>(x, y, zNear, T(1)));
  }
};

// Listing 2: u = fma(-x, mw, mx), v = fma(-y, mw, my), d = cross(u, v). No sign fix, no t_max.
template <typename T>
struct PlaneCrossKernel {
  Vec3<T> mx, my, mw;
  ListingOneOrigin<T> origin;
  int width, height;

  PlaneCrossKernel(const CameraInputs& in, Viewport viewport)
      : origin(in), width(viewport.width), height(viewport.height) {
    const Mat4<T> m(in.clipFromWorld);
    mx = rowXyz(m, 0);
    my = rowXyz(m, 1);
    mw = rowXyz(m, 3);
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> d = glm::cross(fmaVec(-x, mw, mx), fmaVec(-y, mw, my));
    return {origin(x, y), glm::normalize(d), std::numeric_limits<T>::infinity()};
  }
};

// Listing 3: three cross products precomputed (in T), then d = fma(x, my_mw, mx_my),
// d = fma(y, mw_mx, d).
template <typename T>
struct PlaneCrossPreKernel {
  Vec3<T> myCrossMw, mwCrossMx, mxCrossMy;
  ListingOneOrigin<T> origin;
  int width, height;

  PlaneCrossPreKernel(const CameraInputs& in, Viewport viewport)
      : origin(in), width(viewport.width), height(viewport.height) {
    const Mat4<T> m(in.clipFromWorld);
    const Vec3<T> mx = rowXyz(m, 0), my = rowXyz(m, 1), mw = rowXyz(m, 3);
    myCrossMw = glm::cross(my, mw);
    mwCrossMx = glm::cross(mw, mx);
    mxCrossMy = glm::cross(mx, my);
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec3<T> d = fmaVec(y, mwCrossMx, fmaVec(x, myCrossMw, mxCrossMy));
    return {origin(x, y), glm::normalize(d), std::numeric_limits<T>::infinity()};
  }
};

// Listing 4 as published, with z_n set to the near plane of the convention (the listing's comment
// invites that) and the far plane left at z' = 1 as written. Known failures: with an infinite far
// plane dot(mw - mz, d) is exactly zero and the sign of that zero decides the ray's sign; with
// reversed-Z the far plane is z' = 0, not 1.
template <typename T>
struct FullKernel {
  Mat4<T> worldFromClip;
  Vec3<T> mx, my, mz, mw;
  T zNear;
  int width, height;

  FullKernel(const CameraInputs& in, Viewport viewport)
      : worldFromClip(glm::inverse(Mat4<T>(in.clipFromWorld))),
        zNear(T(in.mode.nearNdcZ())),
        width(viewport.width),
        height(viewport.height) {
    const Mat4<T> m(in.clipFromWorld);
    mx = rowXyz(m, 0);
    my = rowXyz(m, 1);
    mz = rowXyz(m, 2);
    mw = rowXyz(m, 3);
  }

  CameraRay<T> operator()(int i, int j) const {
    const T x = clipX<T>(i, width), y = clipX<T>(j, height);
    const Vec4<T> nw = worldFromClip * Vec4<T>(x, y, zNear, T(1));
    const T nFac = T(1) / nw.w;
    const Vec3<T> origin = Vec3<T>(nw) * nFac;
    const Vec3<T> d = glm::cross(fmaVec(-x, mw, mx), fmaVec(-y, mw, my));
    T dFac = T(1) / std::sqrt(glm::dot(d, d));
    const T num = T(1) - zNear;
    const T den = glm::dot(mw - mz, d);
    T tMax = -nFac * num / (dFac * den);
    dFac = tMax > T(0) ? dFac : -dFac;
    tMax = std::abs(tMax);
    return {origin, d * dFac, tMax};
  }
};

#if CLIPRAY_X86
// The other methods' rows, compiled a second time with FMA and AVX2 enabled so their std::fma
// calls become instructions (the comparison with robust stays fair); chosen at run time.
template <typename Kernel, typename T>
__attribute__((target("avx2,fma"))) void rowLoopAvx2(const Kernel& kernel, int j, int width,
                                                     const RaySpan<T>& out) {
  for (int i = 0; i < width; ++i) out.store(i, kernel(i, j));
}
#endif

template <typename Kernel, typename T>
void rowLoopPortable(const Kernel& kernel, int j, int width, const RaySpan<T>& out) {
  for (int i = 0; i < width; ++i) out.store(i, kernel(i, j));
}

template <typename T, typename Kernel>
class KernelGenerator final : public RayGenerator<T> {
 public:
  KernelGenerator(const CameraInputs& inputs, Viewport viewport)
      : RayGenerator<T>(viewport),
        kernel_(inputs, viewport),
        fast_(activeBatchCodePath() >= BatchCodePath::Avx2Fma),
        avx512_(activeBatchCodePath() == BatchCodePath::Avx512) {}

  CameraRay<T> pixelRay(int i, int j) const noexcept override { return kernel_(i, j); }

  void generateRow(int j, const RaySpan<T>& out) const noexcept override {
    const int width = this->viewport().width;
#if CLIPRAY_X86
    if (fast_) {
      if constexpr (std::is_same_v<Kernel, detail::RobustKernel<float>>) {
        if (avx512_) {
          detail::robustRowAvx512(kernel_, j, width, out);
        } else {
          detail::robustRowAvx2(kernel_, j, width, out);
        }
      } else {
        rowLoopAvx2(kernel_, j, width, out);
      }
      return;
    }
#endif
    if constexpr (std::is_same_v<Kernel, detail::RobustKernel<T>>) {
      kernel_.row(j, width, out);
    } else {
      rowLoopPortable(kernel_, j, width, out);
    }
  }

 private:
  Kernel kernel_;
  bool fast_;
  bool avx512_;
};

template <typename T, typename Kernel>
std::unique_ptr<RayGenerator<T>> make(const CameraInputs& inputs, Viewport viewport) {
  return std::make_unique<KernelGenerator<T, Kernel>>(inputs, viewport);
}

}  // namespace

template <typename T>
std::unique_ptr<RayGenerator<T>> makeRayGenerator(RayMethod method, const CameraInputs& inputs,
                                                  Viewport viewport) {
  if (!missingInputs(method, inputs).empty()) return nullptr;
  switch (method) {
    case RayMethod::UnprojectGlm:
      return make<T, UnprojectGlmKernel<T>>(inputs, viewport);
    case RayMethod::TwoPoint:
      return make<T, TwoPointKernel<T>>(inputs, viewport);
    case RayMethod::InversePv:
      return make<T, InversePvKernel<T>>(inputs, viewport);
    case RayMethod::FovTangent:
      return make<T, FovTangentKernel<T>>(inputs, viewport);
    case RayMethod::PlaneCross:
      return make<T, PlaneCrossKernel<T>>(inputs, viewport);
    case RayMethod::PlaneCrossPre:
      return make<T, PlaneCrossPreKernel<T>>(inputs, viewport);
    case RayMethod::Full:
      return make<T, FullKernel<T>>(inputs, viewport);
    case RayMethod::Robust:
      return make<T, detail::RobustKernel<T>>(inputs, viewport);
  }
  return nullptr;
}

std::string batchCodePathName(BatchCodePath path) {
  switch (path) {
    case BatchCodePath::Portable:
      return "portable";
    case BatchCodePath::Avx2Fma:
      return "avx2+fma";
    case BatchCodePath::Avx512:
      return "avx512f+avx2+fma";
  }
  return "?";
}

std::vector<BatchCodePath> supportedBatchCodePaths() {
  std::vector<BatchCodePath> paths = {BatchCodePath::Portable};
  if (kHaveX86 && cpuHasAvx2Fma()) paths.push_back(BatchCodePath::Avx2Fma);
  if (kHaveX86 && cpuHasAvx512()) paths.push_back(BatchCodePath::Avx512);
  return paths;
}

void limitBatchCodePath(std::optional<BatchCodePath> limit) {
  batchCodePathLimit = limit;
}

std::string batchCodePath() {
  return batchCodePathName(activeBatchCodePath());
}

template class RayGenerator<float>;
template class RayGenerator<double>;
template std::unique_ptr<RayGenerator<float>> makeRayGenerator<float>(RayMethod,
                                                                      const CameraInputs&,
                                                                      Viewport);
template std::unique_ptr<RayGenerator<double>> makeRayGenerator<double>(RayMethod,
                                                                        const CameraInputs&,
                                                                        Viewport);

}  // namespace clipray

// The per-pixel classification of a reconcile: the scalar kernel (any pixel) and, beside it, the
// AVX2 kernel for four neighbouring pixels that show the same triangle on both sides, which
// computes the scalar kernel's operations in its order and so gives the same bits.

#include "clipray/compare/PixelClassification.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#define CLIPRAY_COMPARE_AVX2 1
#include <immintrin.h>
#else
#define CLIPRAY_COMPARE_AVX2 0
#endif

#include "clipray/compare/ToleranceTerms.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/rays/FourRays.hpp"
#include "clipray/util/Check.hpp"
#include "clipray/util/KernelChoice.hpp"

namespace clipray::detail {

namespace {

#if CLIPRAY_COMPARE_AVX2
// The per-pixel figures of four neighbouring pixels where both sides show the same triangle, four
// lanes per instruction: the scalar loop's operations in its order (glm's mat4 * vec4 is
// (m0 x + m1 y) + (m2 z + m3 w), its dot products (x + y) + z and (x + y) + (z + w); division and
// square root are correctly rounded; std::max(a, b) is maxpd(b, a), NaN included), so the same
// bits. No FMA in this target: each multiply and add rounds as in the scalar code.
struct FourPolygons {  // the lanes' screen polygons' fields
  double boundX[4], boundY[4], boundZ[4], boundW[4], gradient[4], interpolation[4];
};
struct FourPixels {
  double rayDepth[4], ratio[4], quanta[4], relative[4];
};

// Free functions, not lambdas: GCC 12 does not give a lambda its enclosing function's target.
__attribute__((target("avx2"))) inline __m256d broadcast(double v) {
  return _mm256_set1_pd(v);
}
__attribute__((target("avx2"))) inline __m256d absolute(__m256d v) {
  return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
}
// glm::dot(row, (x, y, z, 1)) = (r.x x + r.y y) + (r.z z + r.w 1), and of (x, y, z) alone
// (r.x x + r.y y) + r.z z.
__attribute__((target("avx2"))) inline __m256d dotPoint(const glm::dvec4& row, __m256d x, __m256d y,
                                                        __m256d z) {
  return _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(broadcast(row.x), x), _mm256_mul_pd(broadcast(row.y), y)),
      _mm256_add_pd(_mm256_mul_pd(broadcast(row.z), z),
                    _mm256_mul_pd(broadcast(row.w), broadcast(1.0))));
}
__attribute__((target("avx2"))) inline __m256d dotDirection(const glm::dvec4& row, __m256d x,
                                                            __m256d y, __m256d z) {
  return _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(broadcast(row.x), x), _mm256_mul_pd(broadcast(row.y), y)),
      _mm256_mul_pd(broadcast(row.z), z));
}

// Four pixels' hits as the scalar code computes them before its tolerance: the rays, the hit
// point in clip space, its window depth, the error against the raster's depth and the storage
// quantum there.
struct FourHits {
  __m256d ox, oy, oz, dx, dy, dz, tMax, t, rasterDepth;
  __m256d c[4];  // m * (o + t d, 1)
  __m256d zNdc, rayDepth, error, quantum;
};

// Returns false (and computes nothing useful) when, under a float depth buffer, a lane's window
// depth is not a finite float (quantumAt then asks depthQuantum): the caller takes the scalar path
// for those four.
__attribute__((target("avx2"))) inline bool loadFourHits(const FourPixelsInput& in, const Ray* rays,
                                                         const Hit* hits,
                                                         const float* rasterDepthFloat,
                                                         FourHits& h) {
  const simd::FourRays four = simd::loadFourRays(rays);
  h.ox = four.originX, h.oy = four.originY, h.oz = four.originZ;
  h.dx = four.directionX, h.dy = four.directionY, h.dz = four.directionZ;
  h.tMax = four.tMax;
  h.t = _mm256_set_pd(hits[3].t, hits[2].t, hits[1].t, hits[0].t);
  h.rasterDepth = _mm256_cvtps_pd(_mm_loadu_ps(rasterDepthFloat));

  // The hit in clip space: m * (o + t d, 1).
  const __m256d px = _mm256_add_pd(h.ox, _mm256_mul_pd(h.t, h.dx));
  const __m256d py = _mm256_add_pd(h.oy, _mm256_mul_pd(h.t, h.dy));
  const __m256d pz = _mm256_add_pd(h.oz, _mm256_mul_pd(h.t, h.dz));
  const glm::dmat4& m = in.clipFromWorld;
  for (int row = 0; row < 4; ++row) {
    h.c[row] =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(broadcast(m[0][row]), px),
                                    _mm256_mul_pd(broadcast(m[1][row]), py)),
                      _mm256_add_pd(_mm256_mul_pd(broadcast(m[2][row]), pz), broadcast(m[3][row])));
  }
  h.zNdc = _mm256_div_pd(h.c[2], h.c[3]);
  h.rayDepth = _mm256_mul_pd(_mm256_sub_pd(h.zNdc, broadcast(in.zn)), broadcast(in.toWindowDepth));
  h.error = absolute(_mm256_sub_pd(h.rasterDepth, h.rayDepth));

  // quantumAt: a fixed-point format's constant, or for Float32 the next float up minus the
  // depth, at least FLT_MIN.
  h.quantum = broadcast(in.fixedQuantum);
  if (in.fixedQuantum == 0.0) {
    const __m128 depthFloat = _mm256_cvtpd_ps(absolute(h.rayDepth));
    const __m128i bits = _mm_castps_si128(depthFloat);
    // Unsigned bits >= 0x7f800000 (inf, NaN; the sign bit is clear): not this path.
    if (_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(bits, _mm_set1_epi32(0x7f7fffff)))) != 0) {
      return false;
    }
    const __m128 next = _mm_castsi128_ps(_mm_add_epi32(bits, _mm_set1_epi32(1)));
    h.quantum = _mm256_max_pd(broadcast(static_cast<double>(std::numeric_limits<float>::min())),
                              _mm256_cvtps_pd(_mm_sub_ps(next, depthFloat)));
  }
  return true;
}

// The figures of four pixels from their hits and tolerances: error over tolerance and over the
// quantum, and the distance along the ray to the raster depth, relative to the distance from the
// eye (or the view volume's depth).
__attribute__((target("avx2"))) inline void finishFour(const FourPixelsInput& in, const FourHits& h,
                                                       __m256d tolerance, FourPixels& out) {
  const __m256d ratio = _mm256_div_pd(h.error, tolerance);
  const __m256d quanta = _mm256_div_pd(h.error, h.quantum);
  const __m256d zRaster =
      _mm256_add_pd(_mm256_mul_pd(h.rasterDepth, broadcast(1.0 - in.zn)), broadcast(in.zn));
  const __m256d z0 = dotPoint(in.rowZ, h.ox, h.oy, h.oz);
  const __m256d z1 = dotDirection(in.rowZ, h.dx, h.dy, h.dz);
  const __m256d w0 = dotPoint(in.rowW, h.ox, h.oy, h.oz);
  const __m256d w1 = dotDirection(in.rowW, h.dx, h.dy, h.dz);
  const __m256d tRaster = _mm256_div_pd(_mm256_sub_pd(z0, _mm256_mul_pd(zRaster, w0)),
                                        _mm256_sub_pd(_mm256_mul_pd(zRaster, w1), z1));
  __m256d scale;
  if (in.parallel) {
    const __m256d finite = _mm256_cmp_pd(
        absolute(h.tMax), broadcast(std::numeric_limits<double>::infinity()), _CMP_LT_OQ);
    scale = _mm256_blendv_pd(h.t, h.tMax, finite);
  } else {
    const __m256d ex = _mm256_sub_pd(h.ox, broadcast(in.eye.x));
    const __m256d ey = _mm256_sub_pd(h.oy, broadcast(in.eye.y));
    const __m256d ez = _mm256_sub_pd(h.oz, broadcast(in.eye.z));
    const __m256d length = _mm256_sqrt_pd(_mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(ex, ex), _mm256_mul_pd(ey, ey)), _mm256_mul_pd(ez, ez)));
    scale = _mm256_add_pd(h.t, length);
  }
  const __m256d relative = _mm256_div_pd(absolute(_mm256_sub_pd(tRaster, h.t)), scale);
  _mm256_storeu_pd(out.rayDepth, h.rayDepth);
  _mm256_storeu_pd(out.ratio, ratio);
  _mm256_storeu_pd(out.quanta, quanta);
  _mm256_storeu_pd(out.relative, relative);
}

// Four pixels showing the same triangle on both sides: triangleDepthTolerance per lane.
__attribute__((target("avx2"))) bool fourTrianglePixels(const FourPixelsInput& in, const Ray* rays,
                                                        const Hit* hits,
                                                        const float* rasterDepthFloat,
                                                        const FourPolygons& polygons,
                                                        FourPixels& out) {
  FourHits h;
  if (!loadFourHits(in, rays, hits, rasterDepthFloat, h)) return false;
  const double u = kFloatUnitRoundoff;
  const __m256d boundX = _mm256_loadu_pd(polygons.boundX),
                boundY = _mm256_loadu_pd(polygons.boundY),
                boundZ = _mm256_loadu_pd(polygons.boundZ),
                boundW = _mm256_loadu_pd(polygons.boundW);
  const __m256d xNdc = _mm256_div_pd(h.c[0], h.c[3]);
  const __m256d yNdc = _mm256_div_pd(h.c[1], h.c[3]);
  const __m256d errorX = _mm256_mul_pd(
      _mm256_mul_pd(_mm256_add_pd(boundX, _mm256_mul_pd(absolute(xNdc), boundW)), broadcast(0.5)),
      broadcast(in.width));
  const __m256d errorY = _mm256_mul_pd(
      _mm256_mul_pd(_mm256_add_pd(boundY, _mm256_mul_pd(absolute(yNdc), boundW)), broadcast(0.5)),
      broadcast(in.height));
  const __m256d xyError = _mm256_max_pd(errorY, errorX);  // std::max(errorX, errorY)
  const __m256d absW = absolute(h.c[3]);
  const __m256d vertexNdc =
      _mm256_div_pd(_mm256_add_pd(boundZ, _mm256_mul_pd(absolute(h.zNdc), boundW)), absW);
  const __m256d xyErrorPixels = _mm256_div_pd(xyError, absW);
  const __m256d vertex = _mm256_add_pd(_mm256_mul_pd(vertexNdc, broadcast(in.toWindow)),
                                       _mm256_mul_pd(broadcast(2.0 * u), absolute(h.rayDepth)));
  const __m256d xyShift = _mm256_add_pd(broadcast(in.subpixelStep), xyErrorPixels);
  const __m256d snap = _mm256_mul_pd(_mm256_loadu_pd(polygons.gradient), xyShift);
  const __m256d tolerance = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(h.quantum, vertex), snap),
                                          _mm256_loadu_pd(polygons.interpolation));
  finishFour(in, h, tolerance, out);
  return true;
}

// What analyticDepthTolerance reads of one analytic primitive.
struct FourAnalytic {
  const glm::dmat4* localFromWorld;
  glm::dvec4 magnitudeRowZ, magnitudeRowW;
  PrimitiveKind kind;
};

// (x x + y y) + z z: glm's dot of a vector with itself, and its length.
__attribute__((target("avx2"))) inline __m256d dotSelf(__m256d x, __m256d y, __m256d z) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)),
                       _mm256_mul_pd(z, z));
}

// Four pixels showing the same analytic primitive on both sides: analyticDepthTolerance
// (AnalyticTolerance.cpp) per lane, in its order. False, as for a non-finite float depth, when a
// lane's error exceeds its tolerance: the scalar path then asks whether the pixel is
// edge-ambiguous.
__attribute__((target("avx2"))) bool fourAnalyticPixels(const FourPixelsInput& in, const Ray* rays,
                                                        const Hit* hits,
                                                        const float* rasterDepthFloat,
                                                        const FourAnalytic& primitive,
                                                        FourPixels& out) {
  FourHits h;
  if (!loadFourHits(in, rays, hits, rasterDepthFloat, h)) return false;
  const double u = kFloatUnitRoundoff;
  const glm::dmat4& l = *primitive.localFromWorld;
  // origin = localFromWorld * (o, 1) (glm's mat4 * vec4), direction = mat3(localFromWorld) * d
  // (glm's mat3 * vec3: (a x + b y) + c z), p = origin + t direction.
  __m256d origin[3], direction[3], p[3];
  for (int r = 0; r < 3; ++r) {
    origin[r] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(broadcast(l[0][r]), h.ox),
                                            _mm256_mul_pd(broadcast(l[1][r]), h.oy)),
                              _mm256_add_pd(_mm256_mul_pd(broadcast(l[2][r]), h.oz),
                                            _mm256_mul_pd(broadcast(l[3][r]), broadcast(1.0))));
    direction[r] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(broadcast(l[0][r]), h.dx),
                                               _mm256_mul_pd(broadcast(l[1][r]), h.dy)),
                                 _mm256_mul_pd(broadcast(l[2][r]), h.dz));
    p[r] = _mm256_add_pd(origin[r], _mm256_mul_pd(h.t, direction[r]));
  }
  // 2. The depth evaluated in float: sum_i M_ri |p_i| from 0.0, then the divide and the mapping.
  __m256d magnitudeZ = _mm256_setzero_pd(), magnitudeW = _mm256_setzero_pd();
  for (int i = 0; i < 4; ++i) {
    const __m256d coordinate = i < 3 ? absolute(p[i]) : broadcast(1.0);
    magnitudeZ =
        _mm256_add_pd(magnitudeZ, _mm256_mul_pd(broadcast(primitive.magnitudeRowZ[i]), coordinate));
    magnitudeW =
        _mm256_add_pd(magnitudeW, _mm256_mul_pd(broadcast(primitive.magnitudeRowW[i]), coordinate));
  }
  const __m256d absW = absolute(h.c[3]);
  const __m256d evaluation = _mm256_add_pd(
      _mm256_mul_pd(
          _mm256_div_pd(
              _mm256_mul_pd(broadcast(6.0 * u),
                            _mm256_add_pd(magnitudeZ, _mm256_mul_pd(absolute(h.zNdc), magnitudeW))),
              absW),
          broadcast(in.analyticToWindow)),
      _mm256_mul_pd(broadcast(2.0 * u), absolute(h.rayDepth)));
  // 3. Where the float ray meets the surface: delta across the ray, delta / cos along it.
  const __m256d originLength = _mm256_sqrt_pd(dotSelf(origin[0], origin[1], origin[2]));
  const __m256d directionLength = _mm256_sqrt_pd(dotSelf(direction[0], direction[1], direction[2]));
  const __m256d delta = _mm256_mul_pd(
      broadcast(32.0 * u), _mm256_add_pd(originLength, _mm256_mul_pd(h.t, directionLength)));
  // glm::normalize(v) = v * (1 / sqrt(dot(v, v))).
  const __m256d directionScale = _mm256_div_pd(broadcast(1.0), directionLength);
  __m256d cosine;
  if (primitive.kind == PrimitiveKind::Sphere) {  // normal p
    const __m256d normalScale =
        _mm256_div_pd(broadcast(1.0), _mm256_sqrt_pd(dotSelf(p[0], p[1], p[2])));
    const __m256d n0 = _mm256_mul_pd(p[0], normalScale), n1 = _mm256_mul_pd(p[1], normalScale),
                  n2 = _mm256_mul_pd(p[2], normalScale);
    cosine =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(n0, _mm256_mul_pd(direction[0], directionScale)),
                                    _mm256_mul_pd(n1, _mm256_mul_pd(direction[1], directionScale))),
                      _mm256_mul_pd(n2, _mm256_mul_pd(direction[2], directionScale)));
  } else if (primitive.kind == PrimitiveKind::Box) {
    // The normal is +-1 on the axis of the largest |p_i| (ties to the lower axis), normalized
    // exactly; the dot product's other terms are 0 * d_i = +-0, which leaves the sum unchanged
    // unless it is itself zero, and |cosine| takes no sign.
    const __m256d a0 = absolute(p[0]), a1 = absolute(p[1]), a2 = absolute(p[2]);
    const __m256d axis0 =
        _mm256_and_pd(_mm256_cmp_pd(a0, a1, _CMP_GE_OQ), _mm256_cmp_pd(a0, a2, _CMP_GE_OQ));
    const __m256d axis1 = _mm256_andnot_pd(axis0, _mm256_cmp_pd(a1, a2, _CMP_GE_OQ));
    const __m256d along =
        _mm256_blendv_pd(_mm256_blendv_pd(direction[2], direction[1], axis1), direction[0], axis0);
    cosine = _mm256_mul_pd(along, directionScale);
  } else {  // disk, quad, plane: the normal (0, 0, 1)
    cosine = _mm256_mul_pd(direction[2], directionScale);
  }
  cosine = absolute(cosine);
  const __m256d alongRay = _mm256_div_pd(
      delta, _mm256_mul_pd(directionLength, _mm256_max_pd(_mm256_sqrt_pd(delta), cosine)));
  // d(window depth)/dt along the world ray: (z' w - z w') / w^2.
  const __m256d zRate = dotDirection(in.rowZ, h.dx, h.dy, h.dz);
  const __m256d wRate = dotDirection(in.rowW, h.dx, h.dy, h.dz);
  const __m256d depthRate = _mm256_mul_pd(
      _mm256_div_pd(
          absolute(_mm256_sub_pd(_mm256_mul_pd(zRate, h.c[3]), _mm256_mul_pd(h.c[2], wRate))),
          _mm256_mul_pd(h.c[3], h.c[3])),
      broadcast(in.analyticToWindow));
  const __m256d tolerance =
      _mm256_add_pd(_mm256_add_pd(h.quantum, evaluation), _mm256_mul_pd(depthRate, alongRay));
  if (_mm256_movemask_pd(_mm256_cmp_pd(h.error, tolerance, _CMP_LE_OQ)) != 0xF) return false;
  finishFour(in, h, tolerance, out);
  return true;
}

bool cpuHasAvx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}
#endif

}  // namespace

FrameClassifier::FrameClassifier(const RasterFrame& raster, const AnalyticFrame& analytic,
                                 const SceneIntersector& intersector, const RasterSetup& setup,
                                 const ToleranceModel& model, PixelComparison& pixels,
                                 unsigned workerCount)
    : raster_(raster),
      analytic_(analytic),
      intersector_(intersector),
      setup_(setup),
      model_(model),
      pixels_(pixels),
      pixelCount_(static_cast<std::size_t>(raster.viewport.width) * raster.viewport.height),
      workerCount_(workerCount),
      primitiveCount_(intersector.primitiveIdCount()),
      rowZ_(matrixRow(setup.clipFromWorld, 2)),
      rowW_(matrixRow(setup.clipFromWorld, 3)),
      parallel_(glm::dvec3(rowW_) == glm::dvec3(0.0)) {
  const glm::dmat4 worldFromClip = glm::inverse(setup.clipFromWorld);
  const glm::dvec4 eyeHomogeneous = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
  eye_ = glm::dvec3(eyeHomogeneous) / eyeHomogeneous.w;
#if CLIPRAY_COMPARE_AVX2
  const DepthConvention convention = setup.mode.convention;
  // The four-pixel kernels map NDC z to window depth for the default depth range only (one for
  // every primitive), never clamp it and add no polygon offset.
  // Nor do they know a depth the shader writes (a logarithmic depth of clip w).
  fourAtOnce_ = cpuHasAvx2() && simdKernelsChosen() && setup.defaultDepthRange() &&
                setup.oneDepthRange() && !setup.depthClamp.enabled && setup.objectOffsets.empty() &&
                !setup.logDepth;
  fourInput_ = {
      setup.clipFromWorld,
      rowZ_,
      rowW_,
      eye_,
      parallel_,
      convention == DepthConvention::ZeroToOne ? 0.0 : -1.0,
      convention == DepthConvention::ZeroToOne ? 1.0 : 0.5,
      model.windowFromNdcScale_,
      model.subpixelStep_,
      static_cast<double>(raster.viewport.width),
      static_cast<double>(raster.viewport.height),
      setup.depthFormat == DepthFormat::Float32 ? 0.0 : depthQuantum(setup.depthFormat, 0.0),
      1.0 / (1.0 - setup.mode.clipVolumeMinZ())};
#endif
  // A parallel camera's distance figure is relative to its ray's interval, which the user clip
  // planes shorten: its plane pixels go along their rays where it has planes.
  // Hits decided from planes come only with computed rays (the screen path's): where a pixel's
  // class is open, its ray path hit.
  if (analytic.planesById && analytic.pixelCentreRays) {
    planePixelHits_.emplace(*analytic.pixelCentreRays, setup.objectClipPlanes);
  }
  // A logarithmic depth is a perspective camera's (a parallel one's clip w is the same everywhere)
  // and never clamped here.
  if (analytic.planesById &&
      (!setup.depthClamp.enabled || (!parallel_ && setup.defaultDepthRange() &&
                                     setup.oneDepthRange() && setup.objectOffsets.empty())) &&
      !(setup.logDepth && (parallel_ || setup.depthClamp.enabled)) &&
      !(parallel_ && (!setup.clipPlanes.empty() || !setup.objectClipPlanes.empty()))) {
    planes_ = analytic.planesById.get();
    planeMapping_ = setup.depthMapping();
    clipXOfColumn_.resize(static_cast<std::size_t>(raster.viewport.width));
    for (int x = 0; x < raster.viewport.width; ++x) {
      clipXOfColumn_[static_cast<std::size_t>(x)] = clipXYOfPixelCentre(x, 0, raster.viewport).x;
    }
    // The four-pixel kernel maps NDC z through the scene's default range or an object's own,
    // with its offset: a logarithmic depth goes pixel by pixel.
    fourPlanes_ = setup.defaultDepthRange() && !setup.logDepth;
#if CLIPRAY_COMPARE_AVX2
    fourPlanesAvx2_ = cpuHasAvx2() && simdKernelsChosen();
#endif
    const bool zeroToOne = setup.mode.convention == DepthConvention::ZeroToOne;
    PlaneFrameConstants& in = planeConstants_;
    in.zn = zeroToOne ? 0.0 : -1.0;
    in.toWindowDepth = zeroToOne ? 1.0 : 0.5;
    in.toWindow = model.windowFromNdcScale_;
    in.subpixelStep = model.subpixelStep_;
    in.width = static_cast<double>(raster.viewport.width);
    in.height = static_cast<double>(raster.viewport.height);
    in.fixedQuantum =
        setup.depthFormat == DepthFormat::Float32 ? 0.0 : depthQuantum(setup.depthFormat, 0.0);
    in.parallel = parallel_;
    in.eyeClipZ = glm::dot(rowZ_, glm::dvec4(eye_, 1.0));
    in.depthSpan = std::abs(setup.mode.farNdcZ() - setup.mode.nearNdcZ());
    in.clampLow = setup.depthClamp.enabled ? 0.0 : -kInf;
    in.clampHigh = setup.depthClamp.enabled ? 1.0 : kInf;
    in.offsets = !setup.objectOffsets.empty();
    in.objectRanges = !setup.oneDepthRange();
  }
}

bool FrameClassifier::fromPlanes(std::size_t i) const {
  return analytic_.planesById && std::isnan(analytic_.hits[i].t) && analytic_.hits[i].hit();
}

KindSamples& FrameClassifier::samplesOf(WorkerSamples& samples, std::size_t kindIndex) const {
  KindSamples& kind = samples[kindIndex];
  if (kind.quanta.capacity() == 0) {
    // Room for this worker's share of the frame up front: growing would copy and touch fresh
    // pages again (reserving only maps address space).
    const std::size_t share = pixelCount_ / workerCount_ + pixelCount_ / 8 + 1;
    kind.quanta.reserve(share);
    kind.relative.reserve(share);
    kind.ratios.reserve(share);
  }
  return kind;
}

std::size_t FrameClassifier::kindOf(std::uint32_t id) const {
  return intersector_.isAnalytic(id)
             ? 1 + static_cast<std::size_t>(intersector_.analyticPrimitive(id).kind)
             : 0;
}

void FrameClassifier::classifyPixel(std::size_t i, glm::dvec2 centre, const Ray& ray,
                                    const Hit& hit, RunMetrics& metrics,
                                    WorkerSamples& samples) const {
  const std::uint32_t rasterId = raster_.ids[i];
  const std::uint32_t rayId = hit.primitiveId;
  // What the images show where nothing below writes: no depth, not compared.
  pixels_.analyticDepth[i] = kNaN;
  pixels_.rasterDepth[i] = std::numeric_limits<float>::quiet_NaN();
  pixels_.toleranceRatio[i] = std::numeric_limits<float>::quiet_NaN();
  pixels_.classes[i] = PixelClass::Background;
  if (rasterId == 0 && rayId == 0) return;  // background
  if (rasterId != 0) {
    ++metrics.rasterHits;
    pixels_.rasterDepth[i] = raster_.depth[i];
  }
  glm::dvec4 hitClip(0.0);
  double zNdc = kNaN, rayDepth = kNaN;
  // Depth clamp: the hit lies beyond the near or far plane and both sides store the range's end.
  bool clamped = false, inFrontOfNear = false;
  if (rayId != 0) {
    ++metrics.rayHits;
    const glm::dvec3 hitPoint = ray.origin + hit.t * ray.direction;
    hitClip = setup_.clipFromWorld * glm::dvec4(hitPoint, 1.0);
    zNdc = hitClip.z / hitClip.w;
    const DepthMapping mapping = setup_.depthMappingOf(rayId);
    if (setup_.depthClamp.enabled) {
      const double mapped = mapping.mappedWindowDepth(zNdc);
      rayDepth = mapping.clampToDepthRange(mapped);
      clamped = rayDepth != mapped;
      inFrontOfNear = clamped && mapping.inFrontOfNear(mapped);
    } else if (setup_.logDepth && !intersector_.isAnalytic(rayId)) {
      // The meshes' shader writes a depth of clip w (LogarithmicDepth.hpp), whatever NDC z is.
      rayDepth = setup_.logDepth->windowDepth(hitClip.w);
    } else {
      rayDepth = mapping.windowDepth(zNdc);
    }
    pixels_.analyticDepth[i] = rayDepth;
  }
  PixelClass& cls = pixels_.classes[i];
  if (rasterId > primitiveCount_ || ray.tMax < 0.0) {
    // An id no primitive has (a renderer bug) or a pixel without a ray: nothing explains it.
    ++metrics.coverageMismatch.total;
    ++metrics.coverageMismatch.unexplained;
    cls = PixelClass::CoverageUnexplained;
  } else if (rasterId == 0 || rayId == 0) {
    ++metrics.coverageMismatch.total;
    cls = classifyMismatch(model_, rayId, rayDepth, 0.0, rasterId, centre);
    ++(cls == PixelClass::CoverageEdgeAmbiguous ? metrics.coverageMismatch.edgeAmbiguous
                                                : metrics.coverageMismatch.unexplained);
  } else if (rasterId == rayId) {
    const bool analyticSurface = intersector_.isAnalytic(rayId);
    const double rasterDepth = raster_.depth[i];
    // A polygon offset: the raster's depth lies in the interval of offsets GL allows from the
    // exact depth (PolygonOffset.hpp), compared with its middle, the tolerance widened by half.
    const OffsetBand band =
        setup_.objectOffsets.empty() || analyticSurface
            ? OffsetBand{rayDepth, 0.0}
            : offsetBand(model_.offsetInterval(rayId), rayDepth, setup_.depthFormat);
    const double exactDepth = rayDepth;
    rayDepth = band.middle;  // analyticDepth keeps the exact depth: the report's offsets
    const double error = std::abs(rasterDepth - rayDepth);
    const double quantum = quantumAt(setup_.depthFormat, rayDepth);
    double tolerance = band.halfWidth;
    if (analyticSurface) {
      tolerance = model_.analyticDepthTolerance(rayId, ray, hit.t);
    } else if (setup_.logDepth) {
      tolerance = model_.logDepthTolerance(rayId, hitClip, quantum);
    } else {
      // depthToleranceAtClip, sharing the hit's depth and quantum.
      tolerance += triangleDepthTolerance(
          model_.pixelTerms(rayId), hitClip, zNdc, exactDepth, quantum,
          setup_.oneDepthRange() ? model_.windowFromNdcScale_
                                 : setup_.depthMappingOf(rayId).windowFromNdcScale(),
          model_.subpixelStep_, raster_.viewport);
    }
    if (analyticSurface && !(error <= tolerance) && model_.analyticEdgeAmbiguous(rayId, centre)) {
      // The same sphere or box, but one side entered the surface where the other
      // started inside it (the near plane cuts the shape within float error of this
      // pixel): the front surface's coverage is ambiguous here, not the depth of
      // either surface.
      ++metrics.coverageMismatch.total;
      ++metrics.coverageMismatch.edgeAmbiguous;
      cls = PixelClass::CoverageEdgeAmbiguous;
      return;
    }
    const auto [ratio, quanta] = divideTwo(error, tolerance, error, quantum);
    if (clamped && ratio <= 1.0) {
      // Both sides store the depth range's end: nothing to measure along the ray. In front of the
      // near plane a class of its own (what a near-plane picking ray cannot reach).
      pixels_.toleranceRatio[i] = static_cast<float>(ratio);
      metrics.inFrontOfNear += inFrontOfNear ? 1 : 0;
      cls = inFrontOfNear ? PixelClass::InFrontOfNear : PixelClass::Agree;
      return;
    }
    // Distance along the ray to where the raster depth lies: z(t) = (Z0 + Z1 t)/(W0 + W1 t), or
    // for a logarithmic depth w(t) = W0 + W1 t.
    const double z0 = glm::dot(rowZ_, glm::dvec4(ray.origin, 1.0));
    const double z1 = glm::dot(glm::dvec3(rowZ_), ray.direction);
    const double w0 = glm::dot(rowW_, glm::dvec4(ray.origin, 1.0));
    const double w1 = glm::dot(glm::dvec3(rowW_), ray.direction);
    double tRaster = 0.0;
    if (setup_.logDepth && !analyticSurface) {
      tRaster = (setup_.logDepth->clipWOfWindowDepth(rasterDepth) - w0) / w1;
    } else {
      const double zRaster =
          setup_.depthMappingOf(rayId).ndcOfWindowDepth(rasterDepth - (rayDepth - exactDepth));
      tRaster = (z0 - zRaster * w0) / (zRaster * w1 - z1);
    }
    // Relative to the distance from the eye (perspective) or the view volume's depth
    // (orthographic), so the figure reads the same at any scale.
    const double scale = parallel_ ? (std::isfinite(ray.tMax) ? ray.tMax : hit.t)
                                   : hit.t + glm::length(ray.origin - eye_);
    ++metrics.depthCompared;
    KindSamples& kind = samplesOf(samples, analyticSurface ? kindOf(rayId) : 0);
    kind.quanta.push_back(quanta);
    kind.relative.push_back(std::abs(tRaster - hit.t) / scale);
    kind.ratios.push_back(ratio);
    pixels_.toleranceRatio[i] = static_cast<float>(ratio);
    if (!(ratio <= 1.0)) {  // NaN counts as beyond tolerance
      ++metrics.depthBeyondTolerance;
      cls = PixelClass::DepthBeyondTolerance;
    } else {
      cls = PixelClass::Agree;
    }
  } else {
    ++metrics.idMismatch.total;
    double rayTolerance = intersector_.isAnalytic(rayId)
                              ? model_.analyticDepthTolerance(rayId, ray, hit.t)
                              : model_.depthToleranceAtClip(rayId, hitClip);
    double comparedDepth = rayDepth;
    if (setup_.logDepth && !intersector_.isAnalytic(rayId)) {
      // Which surface is nearer is the same question in projective depth (both depths grow with
      // t along the ray): the other surface's depth there is projective (surfaceDepthAt), so the
      // hit's is too, its tolerance widened by the log depth's, carried over by the slope of
      // projective depth against the log depth at the hit.
      const DepthMapping mapping = setup_.depthMappingOf(rayId);
      comparedDepth = mapping.windowDepth(zNdc);
      const double logTolerance =
          model_.logDepthTolerance(rayId, hitClip, quantumAt(setup_.depthFormat, rayDepth));
      const double dzdt = (glm::dot(glm::dvec3(rowZ_), ray.direction) * hitClip.w -
                           hitClip.z * glm::dot(glm::dvec3(rowW_), ray.direction)) /
                          (hitClip.w * hitClip.w) * mapping.windowFromNdcScale();
      const double dldt =
          setup_.logDepth->slope(hitClip.w) * glm::dot(glm::dvec3(rowW_), ray.direction);
      rayTolerance += logTolerance * std::abs(dzdt / dldt);
    }
    cls = classifyMismatch(model_, rayId, comparedDepth, rayTolerance, rasterId, centre);
    if (inFrontOfNear && cls == PixelClass::IdDepthAmbiguous) {
      // Two surfaces in front of the near plane, both at the near depth: the first drawn shows
      // (the strict depth test keeps it), the rays see the nearest. Neither is measurable there.
      --metrics.idMismatch.total;
      ++metrics.inFrontOfNear;
      cls = PixelClass::InFrontOfNear;
      return;
    }
    ++(cls == PixelClass::IdDepthAmbiguous  ? metrics.idMismatch.depthAmbiguous
       : cls == PixelClass::IdEdgeAmbiguous ? metrics.idMismatch.edgeAmbiguous
                                            : metrics.idMismatch.unexplained);
  }
}

bool FrameClassifier::classifyFour(std::size_t first, const Ray* rays, RunMetrics& metrics,
                                   WorkerSamples& samples) const {
#if CLIPRAY_COMPARE_AVX2
  const std::uint32_t* rasterIds = &raster_.ids[first];
  const Hit* hits = &analytic_.hits[first];
  for (std::size_t l = 0; l < 4; ++l) {
    // A hit decided from planes has no t (NaN): not this kernel's.
    if (rasterIds[l] == 0 || rasterIds[l] != hits[l].primitiveId || rays[l].tMax < 0.0 ||
        std::isnan(hits[l].t)) {
      return false;
    }
  }
  if (rasterIds[0] > primitiveCount_) return false;
  FourPixels figures;
  std::size_t kindIndex = 0;
  if (intersector_.isAnalytic(rasterIds[0])) {
    // Four pixels of one analytic primitive (a sphere's, a box's: most of their pixels).
    const std::uint32_t id = rasterIds[0];
    if (rasterIds[1] != id || rasterIds[2] != id || rasterIds[3] != id) return false;
    const AnalyticPrimitive& primitive = intersector_.analyticPrimitive(id);
    const ToleranceModel::AnalyticTransform& transform =
        model_.analyticTransforms_[id - 1 - intersector_.triangleCount()];
    const FourAnalytic four{&primitive.localFromWorld, transform.magnitudeRowZ,
                            transform.magnitudeRowW, primitive.kind};
    if (!fourAnalyticPixels(fourInput_, rays, hits, &raster_.depth[first], four, figures)) {
      return false;
    }
    kindIndex = kindOf(id);
  } else {
    FourPolygons polygons;
    std::uint32_t previousId = 0;
    const ToleranceModel::PixelTerms* terms = nullptr;
    for (std::size_t l = 0; l < 4; ++l) {
      const std::uint32_t rasterId = rasterIds[l];
      // Neighbouring pixels mostly show one triangle: its terms are looked up once.
      if (rasterId != previousId) {
        if (rasterId > primitiveCount_ || intersector_.isAnalytic(rasterId)) return false;
        const std::uint32_t slot = model_.slotOfId_[rasterId];
        if (slot == ToleranceModel::kNoSlot) return false;
        terms = &model_.pixelTerms_[slot];
        previousId = rasterId;
      }
      polygons.boundX[l] = terms->clipErrorBound.x;
      polygons.boundY[l] = terms->clipErrorBound.y;
      polygons.boundZ[l] = terms->clipErrorBound.z;
      polygons.boundW[l] = terms->clipErrorBound.w;
      polygons.gradient[l] = terms->gradient;
      polygons.interpolation[l] = terms->interpolation;
    }
    if (!fourTrianglePixels(fourInput_, rays, hits, &raster_.depth[first], polygons, figures)) {
      return false;
    }
  }
  // The four pixels' figures and images, as classifyPixel writes them one by one
  // (the samples in the same order).
  KindSamples& kind = samplesOf(samples, kindIndex);
  metrics.rasterHits += 4;
  metrics.rayHits += 4;
  metrics.depthCompared += 4;
  std::memcpy(&pixels_.rasterDepth[first], &raster_.depth[first], 4 * sizeof(float));
  std::memcpy(&pixels_.analyticDepth[first], figures.rayDepth, 4 * sizeof(double));
  appendFour(kind.quanta, figures.quanta);
  appendFour(kind.relative, figures.relative);
  appendFour(kind.ratios, figures.ratio);
  for (std::size_t l = 0; l < 4; ++l) {
    pixels_.toleranceRatio[first + l] = static_cast<float>(figures.ratio[l]);
    const bool beyond = !(figures.ratio[l] <= 1.0);  // NaN counts as beyond tolerance
    metrics.depthBeyondTolerance += beyond ? 1 : 0;
    pixels_.classes[first + l] = beyond ? PixelClass::DepthBeyondTolerance : PixelClass::Agree;
  }
  return true;
#else
  (void)first, (void)rays, (void)metrics, (void)samples;
  return false;
#endif
}

void FrameClassifier::classifyRows(int rowBegin, int rowEnd, RunMetrics& metrics,
                                   WorkerSamples& samples) const {
  const std::size_t width = static_cast<std::size_t>(raster_.viewport.width);
  metrics.pixels = static_cast<std::int64_t>(width) * (rowEnd - rowBegin);
  // The row goes in runs of 64 pixels. A run that shows nothing on either side (a terrain's
  // sky, most of a small scene's frame) only gets the background's images, written at once.
  // The others get their rays where the frame computes them (robustRayFrame: 107 KB at 1920
  // pixels, read from this core's cache) when a pixel of the run first reads one: a background
  // pixel never does, nor one the screen path's planes classify.
  constexpr std::size_t kRun = 64;
  // Runs start at multiples of 4: classifyFour's four pixels never straddle two.
  static_assert(kRun % 4 == 0);
  std::vector<Ray> rowScratch(analytic_.pixelCentreRays ? width : 0);
  std::vector<std::uint8_t> runShows((width + kRun - 1) / kRun);
  std::vector<std::uint8_t> runRays((width + kRun - 1) / kRun);
  const bool planeHits = analytic_.planesById != nullptr;
  for (int y = rowBegin; y < rowEnd; ++y) {
    const std::size_t rowStart = static_cast<std::size_t>(y) * width;
    const double centreY = y + 0.5;
    const double yNdc = clipXYOfPixelCentre(0, y, raster_.viewport).y;
    const Ray* rowRays =
        analytic_.pixelCentreRays ? rowScratch.data() : analytic_.rays.data() + rowStart;
    for (std::size_t x0 = 0; x0 < width; x0 += kRun) {
      const std::size_t n = std::min(kRun, width - x0);
      std::uint32_t shown = 0;
      for (std::size_t k = rowStart + x0; k < rowStart + x0 + n; ++k) {
        shown |= raster_.ids[k] | analytic_.hits[k].primitiveId;
      }
      runShows[x0 / kRun] = shown != 0 ? 1 : 0;
      runRays[x0 / kRun] = analytic_.pixelCentreRays ? 0 : 1;
    }
    // The rays of pixel x's run, computed when the run first needs them.
    const auto raysOf = [&](std::size_t x) {
      const std::size_t run = x / kRun;
      if (runRays[run] == 0) {
        const std::size_t first = run * kRun;
        analytic_.pixelCentreRays->row(y, static_cast<int>(first),
                                       static_cast<int>(std::min(kRun, width - first)),
                                       rowScratch.data() + first);
        runRays[run] = 1;
      }
      return rowRays + x;
    };
    for (std::size_t x = 0; x < width; ++x) {
      if (x % kRun == 0 && runShows[x / kRun] == 0) {
        // What the loop below writes at a background pixel, for the whole run.
        const std::size_t first = rowStart + x, n = std::min(kRun, width - x);
        std::fill_n(&pixels_.analyticDepth[first], n, kNaN);
        std::fill_n(&pixels_.rasterDepth[first], n, std::numeric_limits<float>::quiet_NaN());
        std::fill_n(&pixels_.toleranceRatio[first], n, std::numeric_limits<float>::quiet_NaN());
        std::fill_n(&pixels_.classes[first], n, PixelClass::Background);
        x += n - 1;
        continue;
      }
      const std::size_t i = rowStart + x;
      const glm::dvec2 centre(static_cast<double>(x) + 0.5, centreY);
      if (fourPlanes_ && x % 4 == 0 && x + 4 <= width &&
          classifyFourFromPlanes(i, &clipXOfColumn_[x], yNdc, metrics, samples)) {
        x += 3;
        continue;
      }
      if (planeHits && fromPlanes(i)) {
        if (planes_ && classifyFromPlanes(i, clipXOfColumn_[x], yNdc, metrics, samples)) continue;
        const Ray& ray = *raysOf(x);
        CLIPRAY_CHECK(planePixelHits_.has_value(),
                      "a hit decided from planes without computed rays");
        classifyPixel(i, centre, ray,
                      planePixelHits_->rayPathHit(intersector_, analytic_.hits[i].primitiveId,
                                                  static_cast<int>(x), y, ray),
                      metrics, samples);
        ++metrics.planePixels.alongRays;
        continue;
      }
      if (fourAtOnce_ && x % 4 == 0 && x + 4 <= width && raster_.ids[i] != 0 &&
          classifyFour(i, raysOf(x), metrics, samples)) {
        x += 3;
        continue;
      }
      classifyPixel(i, centre, *raysOf(x), analytic_.hits[i], metrics, samples);
    }
  }
}

}  // namespace clipray::detail

namespace clipray {

PixelClass classifyMismatch(const ToleranceModel& model, std::uint32_t rayId, double rayDepth,
                            double rayTolerance, std::uint32_t rasterId, glm::dvec2 centre) {
  if (rasterId == 0 || rayId == 0) {
    const std::uint32_t shown = rasterId != 0 ? rasterId : rayId;
    return model.edgeAmbiguous(shown, centre) || model.onClipPlane(shown)
               ? PixelClass::CoverageEdgeAmbiguous
               : PixelClass::CoverageUnexplained;
  }
  // Where does the raster's primitive lie along this pixel? Its depth at the centre (plane or
  // analytic surface) and the tolerance there.
  // Each side moved by its polygon offset, if any (the middle of what GL allows, the tolerance
  // widened by the half width): a decal pushed off its wall is not ambiguous with it.
  const OffsetInterval rasterOffset = model.offsetInterval(rasterId);
  const OffsetInterval rayOffset = model.offsetInterval(rayId);
  const double rasterSurfaceDepth = model.surfaceDepthAt(rasterId, centre) + rasterOffset.middle();
  const double tolerance = rayTolerance + model.surfaceToleranceAt(rasterId, centre) +
                           rasterOffset.halfWidth() + rayOffset.halfWidth();
  if (std::abs(rasterSurfaceDepth - (rayDepth + rayOffset.middle())) <= tolerance) {
    return PixelClass::IdDepthAmbiguous;
  }
  if (model.edgeAmbiguous(rasterId, centre) || model.edgeAmbiguous(rayId, centre) ||
      model.onClipPlane(rasterId) || model.onClipPlane(rayId)) {
    return PixelClass::IdEdgeAmbiguous;
  }
  return PixelClass::IdUnexplained;
}

}  // namespace clipray

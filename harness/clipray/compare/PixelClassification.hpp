#pragma once
// Internal to compare/: the per-pixel classification of a reconcile. Each pixel gets its class,
// its images' values and (where both sides show the same primitive) its depth figures; the
// scalar kernel takes any pixel, the AVX2 kernel four neighbouring pixels of one triangle, with
// the same bits.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/compare/PlanePixelHits.hpp"
#include "clipray/compare/Reconcile.hpp"

namespace clipray::detail {

// Surface kinds the depth figures are split by: 0 triangles, 1 + PrimitiveKind for analytic
// primitives.
inline constexpr std::size_t kSurfaceKinds = 1 + static_cast<std::size_t>(PrimitiveKind::Plane) + 1;

// The three figures of one kind, as gathered by one worker (kept apart until the end: the
// distributions read the parts where they lie).
struct KindSamples {
  FrameVector<double> quanta, relative, ratios;
};
using WorkerSamples = std::array<KindSamples, kSurfaceKinds>;

// Appends four values with one size check (the samples are reserved for the frame up front).
inline void appendFour(FrameVector<double>& values, const double four[4]) {
  const std::size_t size = values.size();
  values.resize(size + 4);  // left unwritten by the allocator; written here
  std::memcpy(values.data() + size, four, 4 * sizeof(double));
}

// What the AVX2 kernel reads besides the pixels: the frame's constants, as doubles.
struct FourPixelsInput {
  glm::dmat4 clipFromWorld;
  glm::dvec4 rowZ, rowW;
  glm::dvec3 eye;
  bool parallel;
  double zn;             // the convention's near NDC z
  double toWindowDepth;  // 1 / (1 - zn): exact (a power of two), so (z - zn) / (1 - zn) too
  double toWindow;       // the tolerance model's 1 / (1 - clipVolumeMinZ)
  double subpixelStep;
  double width, height;  // the viewport, as doubles
  // The depth quantum of a fixed-point format (2^-16, 2^-24: the same at every depth); 0 for a
  // float depth buffer, whose quantum the kernel computes per pixel.
  double fixedQuantum;
  double analyticToWindow;  // analyticDepthTolerance's 1 / (1 - clipVolumeMinZ)
};

// What the four-pixel kernel of the screen path's planes reads (PlaneClassification.cpp): the
// frame's constants, and per pixel its triangle's planes and tolerance terms (the same for all
// four where `one` says so: most groups of a mesh).
struct PlaneFrameConstants {
  double zn, toWindowDepth;  // the convention's near NDC z and 1 / (1 - zn) (exact)
  double toWindow;           // the tolerance model's 1 / (1 - clipVolumeMinZ)
  double subpixelStep, width, height;
  double fixedQuantum;  // a fixed-point format's quantum; 0 for a float depth buffer
  bool parallel;
  double eyeClipZ;   // the eye's clip z (its x, y and w are 0): distances along a sight line
  double depthSpan;  // |z_far - z_near| in NDC: a parallel camera's depth of view
  // Under depth clamp the depth range's ends (0 and 1): a pixel whose depth lies within its
  // planes' reach of either may be clamped, and the ray path decides it; else -inf and +inf.
  double clampLow, clampHigh;
  // Objects drawn with a polygon offset: the raster's depth is compared with the middle of the
  // depths GL allows (PolygonOffset.hpp's offsetBand), the tolerance widened by their half width.
  bool offsets;
  // Objects drawn with a depth range of their own: each pixel's window depth through its
  // object's (FourPlanePixels' rangeLow and rangeSpan).
  bool objectRanges;
};
struct FourPlanePixels {
  const TrianglePlanes* planes[4];
  const glm::dvec4* clipErrorBound[4];  // the tolerance model's PixelTerms
  const double* gradient[4];
  const double* interpolation[4];
  bool one;  // all four the same triangle
  // Where the frame has objects' own ranges, each pixel's object's glDepthRange(n, f) as n and
  // f - n, and where it has offsets, its object's OffsetInterval (0 and 0: none).
  double rangeLow[4], rangeSpan[4], offsetLow[4], offsetHigh[4];
  const double* xNdc;
  double yNdc;
  const float* rasterDepth;
};
// One plane pixel's figures before its class: its window depth, the depth the raster's is
// compared with (under a polygon offset the middle of what GL allows), the tolerance and
// quantum, how far the ray path's depth may lie from it (reach) and its tolerance (beyond 2^-20
// of itself: toleranceReach), and the raster depth's distance from the hit relative to the hit's
// (the report's relative figure).
struct PlaneFigures {
  double depth, compared, tolerance, quantum, reach, toleranceReach, relative;
};
struct FourPlaneFigures {
  double depth[4], ratio[4], quanta[4], relative[4];
};

// The per-frame constants of the classification; classifyRows runs on any number of threads at
// once, each with its own rows, metrics and samples.
class FrameClassifier {
 public:
  // pixels' images must be sized to the frame already; workerCount sizes each worker's samples.
  FrameClassifier(const RasterFrame& raster, const AnalyticFrame& analytic,
                  const SceneIntersector& intersector, const RasterSetup& setup,
                  const ToleranceModel& model, PixelComparison& pixels, unsigned workerCount);

  // Classifies rows [rowBegin, rowEnd): writes their pixels' images, counts them into metrics
  // and appends their depth figures to samples (in pixel order).
  void classifyRows(int rowBegin, int rowEnd, RunMetrics& metrics, WorkerSamples& samples) const;

 private:
  // The samples of one surface kind, with room for this worker's share of the frame.
  KindSamples& samplesOf(WorkerSamples& samples, std::size_t kindIndex) const;
  std::size_t kindOf(std::uint32_t id) const;
  // The scalar kernel: pixel i, whose centre lies at window position centre, its ray and hit
  // given (the ray read only where the pixel shows something).
  void classifyPixel(std::size_t i, glm::dvec2 centre, const Ray& ray, const Hit& hit,
                     RunMetrics& metrics, WorkerSamples& samples) const;
  // Pixel i, decided by the screen path from its triangle's planes (AnalyticFrame::planesById),
  // whose centre lies at NDC (xNdc, yNdc): its figures from the planes where both sides show that
  // triangle and the class is certain (PlaneClassification.cpp); false (nothing written) where
  // the ray path must classify it.
  bool classifyFromPlanes(std::size_t i, double xNdc, double yNdc, RunMetrics& metrics,
                          WorkerSamples& samples) const;
  // Its figures where the raster stores the projective depth (planeMapping_), or a logarithmic
  // depth of clip w (setup_.logDepth, a perspective camera without depth clamp); false where the
  // depth may be clamped or the planes' bounds leave the ray path's depth too far.
  bool projectiveDepthFromPlanes(const TrianglePlanes& planes, std::uint32_t id, std::uint32_t slot,
                                 double xNdc, double yNdc, double zNdc, double reciprocalW,
                                 double rasterDepth, PlaneFigures& out) const;
  bool logDepthFromPlanes(const TrianglePlanes& planes, std::uint32_t id, double xNdc, double yNdc,
                          double reciprocalW, double rasterDepth, PlaneFigures& out) const;
  // Pixels first .. first + 3, at NDC (xNdc[l], yNdc), the same four at once where all four were
  // decided from planes, show their triangle on both sides and are certain; false (nothing
  // written) otherwise.
  bool classifyFourFromPlanes(std::size_t first, const double* xNdc, double yNdc,
                              RunMetrics& metrics, WorkerSamples& samples) const;
  // Whether pixel i's hit was decided from planes (no ray traced: t is NaN).
  bool fromPlanes(std::size_t i) const;
  // Pixels first .. first + 3 through the AVX2 kernels when each shows the same triangle on both
  // sides (with a ray and a polygon built up front), or all four the same analytic primitive
  // within its depth tolerance; false (nothing written) otherwise.
  bool classifyFour(std::size_t first, const Ray* rays, RunMetrics& metrics,
                    WorkerSamples& samples) const;

  const RasterFrame& raster_;
  const AnalyticFrame& analytic_;
  const SceneIntersector& intersector_;
  const RasterSetup& setup_;
  const ToleranceModel& model_;
  PixelComparison& pixels_;
  std::size_t pixelCount_;
  unsigned workerCount_;
  std::uint32_t primitiveCount_;
  glm::dvec4 rowZ_, rowW_;  // rows 2 and 3 of clipFromWorld
  bool parallel_;           // an orthographic camera: no eye point
  glm::dvec3 eye_;
  // Four pixels at a time where all four show the same triangle on both sides (most pixels of a
  // mesh), on a CPU with AVX2.
  bool fourAtOnce_ = false;
  FourPixelsInput fourInput_{};
  // The screen path's planes, where the frame has them and this setup stores the projective depth
  // (through the objects' own depth ranges and polygon offsets too) or a perspective camera's
  // logarithmic depth; depth clamp only with the default range, no object's own and a
  // perspective camera, whose rays' distances are the sight lines' from the eye. Else null, and
  // its pixels are classified along their rays.
  const FrameVector<TrianglePlanes>* planes_ = nullptr;
  DepthMapping planeMapping_{};
  std::vector<double> clipXOfColumn_;  // NDC x of each column's pixel centre
  // Four plane pixels at a time under the default depth range (on AVX2 lanes where the CPU has
  // them and the SIMD kernels are chosen, else on the baseline's: the same bits).
  bool fourPlanes_ = false;
  bool fourPlanesAvx2_ = false;
  PlaneFrameConstants planeConstants_{};  // both plane kernels' frame constants
  // Where the frame's rays are computed: the ray path's hit of a plane pixel whose class the
  // planes leave open (along its group's ray).
  std::optional<PlanePixelHits> planePixelHits_;
};

}  // namespace clipray::detail

// Reconciliation of a raster frame with an analytic frame: the tolerance model built for the
// primitives the raster shows, the pixels classified across threads (PixelClassification.cpp),
// their counts merged and the distributions of their depth figures computed.

#include "clipray/compare/Reconcile.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "clipray/compare/Distributions.hpp"
#include "clipray/compare/PixelClassification.hpp"
#include "clipray/util/Check.hpp"

namespace clipray {

const char* pixelClassName(PixelClass value) {
  switch (value) {
    case PixelClass::Background:
      return "background";
    case PixelClass::Agree:
      return "agree";
    case PixelClass::DepthBeyondTolerance:
      return "depth_beyond_tolerance";
    case PixelClass::CoverageEdgeAmbiguous:
      return "coverage_edge_ambiguous";
    case PixelClass::CoverageUnexplained:
      return "coverage_unexplained";
    case PixelClass::IdDepthAmbiguous:
      return "id_depth_ambiguous";
    case PixelClass::IdEdgeAmbiguous:
      return "id_edge_ambiguous";
    case PixelClass::IdUnexplained:
      return "id_unexplained";
    case PixelClass::InFrontOfNear:
      return "in_front_of_near";
  }
  return "?";
}

namespace {

// The triangles and primitives the raster shows (ascending): the ids the tolerance model is
// asked about in every pixel that compares depth (there the rays show the same id). On a big
// scene far fewer than all of them. The few ids only the rays show are asked about at mismatched
// pixels alone, and built there (ToleranceModel::polygon); reading the hits here too read 40 MB
// of a 1080p frame where the raster ids are 8 MB.
std::vector<std::uint32_t> idsInRaster(const RasterFrame& raster, std::uint32_t primitiveCount,
                                       unsigned threadCount) {
  std::vector<std::uint8_t> shown(std::size_t{primitiveCount} + 1, 0);
  const Viewport viewport = raster.viewport;
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    // Every id marked with a store and no branch (a mesh's small triangles change the id every
    // few pixels: a branch on "same as the last" mispredicted there). Threads may mark the same
    // id: relaxed atomics make that well-defined (plain byte stores on x86). Background and
    // invalid ids mark a byte of this thread's own, not one every thread writes.
    std::uint8_t elsewhere = 0;
    const std::size_t begin = static_cast<std::size_t>(rowBegin) * viewport.width;
    const std::size_t end = static_cast<std::size_t>(rowEnd) * viewport.width;
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t id = raster.ids[i];
      std::uint8_t& flag = id != 0 && id <= primitiveCount ? shown[id] : elsewhere;
      std::atomic_ref<std::uint8_t>(flag).store(1, std::memory_order_relaxed);
    }
  });
  std::vector<std::uint32_t> ids;
  for (std::uint32_t id = 1; id <= primitiveCount; ++id) {
    if (shown[id] != 0) ids.push_back(id);
  }
  return ids;
}

void requireComparableFrames(const RasterFrame& raster, const AnalyticFrame& analytic) {
  const Viewport viewport = raster.viewport;
  const std::size_t count = static_cast<std::size_t>(viewport.width) * viewport.height;
  CLIPRAY_CHECK(analytic.viewport == viewport && raster.depth.size() == count &&
                    raster.ids.size() == count && analytic.hits.size() == count,
                "compareFrames: raster and analytic frames differ in size");
  CLIPRAY_CHECK(
      analytic.hasRays(),
      "compareFrames: the analytic frame needs one ray per pixel, stored or computed (not both)");
}

}  // namespace

std::unique_ptr<ToleranceModel> toleranceModelOfRaster(const RasterFrame& raster,
                                                       const SceneIntersector& intersector,
                                                       const RasterSetup& setup,
                                                       unsigned threadCount) {
  // Screen polygons only for the primitives the frame shows (a big scene's other triangles are
  // never asked about), clipped across the threads.
  const Viewport viewport = raster.viewport;
  CLIPRAY_CHECK(raster.ids.size() == static_cast<std::size_t>(viewport.width) * viewport.height,
                "toleranceModelOfRaster: the raster's ids differ from its size");
  return std::make_unique<ToleranceModel>(
      intersector, setup, raster.viewport,
      idsInRaster(raster, intersector.primitiveIdCount(), threadCount), threadCount);
}

ComparisonResult compareFrames(const RasterFrame& raster, const AnalyticFrame& analytic,
                               const SceneIntersector& intersector, const RasterSetup& setup,
                               unsigned threadCount) {
  requireComparableFrames(raster, analytic);
  const std::unique_ptr<ToleranceModel> model =
      toleranceModelOfRaster(raster, intersector, setup, threadCount);
  return compareFrames(raster, analytic, intersector, setup, *model, threadCount);
}

ComparisonResult compareFrames(const RasterFrame& raster, const AnalyticFrame& analytic,
                               const SceneIntersector& intersector, const RasterSetup& setup,
                               const ToleranceModel& model, unsigned threadCount) {
  const RasterSetup& modelSetup = model.setup();
  CLIPRAY_CHECK(modelSetup.clipFromWorld == setup.clipFromWorld && modelSetup.mode == setup.mode &&
                    modelSetup.depthFormat == setup.depthFormat &&
                    modelSetup.vertexMode == setup.vertexMode &&
                    modelSetup.vertexReference == setup.vertexReference &&
                    modelSetup.subpixelBits == setup.subpixelBits &&
                    modelSetup.objectDepthRanges == setup.objectDepthRanges &&
                    modelSetup.objectClipPlanes == setup.objectClipPlanes &&
                    modelSetup.objectOffsets == setup.objectOffsets &&
                    modelSetup.logDepth == setup.logDepth && model.viewport() == raster.viewport,
                "compareFrames: the tolerance model answers for another setup");
  requireComparableFrames(raster, analytic);
  const Viewport viewport = raster.viewport;
  const std::size_t count = static_cast<std::size_t>(viewport.width) * viewport.height;
  // Each worker's depth figures per surface kind, kept apart until the distributions.
  const unsigned workerCount = parallelWorkerCount(viewport.height, threadCount);
  std::vector<detail::WorkerSamples> samplesOfWorker(workerCount);

  ComparisonResult result;
  PixelComparison& pixels = result.pixels;
  pixels.viewport = viewport;
  // Frame buffers (a previous run's pages where one of the same size was released), left unwritten
  // here: the classification writes all four images at every pixel, so they are written once, on
  // the threads (a fill would write a 1080p frame's 35 MB of images twice).
  pixels.analyticDepth.resize(count);
  pixels.rasterDepth.resize(count);
  pixels.toleranceRatio.resize(count);
  pixels.classes.resize(count);

  std::mutex merge;
  RunMetrics& total = result.metrics;
  const detail::FrameClassifier classifier(raster, analytic, intersector, setup, model, pixels,
                                           workerCount);
  parallelForRowsByWorker(
      viewport.height, threadCount, [&](unsigned worker, int rowBegin, int rowEnd) {
        RunMetrics local;
        classifier.classifyRows(rowBegin, rowEnd, local, samplesOfWorker[worker]);
        const std::lock_guard<std::mutex> lock(merge);
        total.pixels += local.pixels;
        total.rasterHits += local.rasterHits;
        total.rayHits += local.rayHits;
        total.coverageMismatch.total += local.coverageMismatch.total;
        total.coverageMismatch.edgeAmbiguous += local.coverageMismatch.edgeAmbiguous;
        total.coverageMismatch.unexplained += local.coverageMismatch.unexplained;
        total.idMismatch.total += local.idMismatch.total;
        total.idMismatch.depthAmbiguous += local.idMismatch.depthAmbiguous;
        total.idMismatch.edgeAmbiguous += local.idMismatch.edgeAmbiguous;
        total.idMismatch.unexplained += local.idMismatch.unexplained;
        total.depthCompared += local.depthCompared;
        total.depthBeyondTolerance += local.depthBeyondTolerance;
        total.inFrontOfNear += local.inFrontOfNear;
        total.planePixels.fromPlanes += local.planePixels.fromPlanes;
        total.planePixels.alongRays += local.planePixels.alongRays;
      });

  // Every distribution to compute: per kind with samples, then over all kinds. Where one kind
  // holds every sample, the overall figures are that kind's (the same values, so the same
  // quantiles) and are not computed twice.
  using Parts = std::vector<const FrameVector<double>*>;
  struct Job {
    Parts parts;
    Distribution* into;
  };
  std::vector<Job> jobs;
  std::vector<std::size_t> kindsWithSamples;
  for (std::size_t k = 0; k < detail::kSurfaceKinds; ++k) {
    for (const auto& worker : samplesOfWorker) {
      if (!worker[k].quanta.empty()) {
        kindsWithSamples.push_back(k);
        break;
      }
    }
  }
  total.byKind.resize(kindsWithSamples.size());
  Parts allQuanta, allRelative, allRatios;
  for (std::size_t n = 0; n < kindsWithSamples.size(); ++n) {
    const std::size_t k = kindsWithSamples[n];
    RunMetrics::KindFigures& figures = total.byKind[n];
    figures.kind = k == 0 ? "triangle" : primitiveKindName(static_cast<PrimitiveKind>(k - 1));
    Parts quanta, relative, ratios;
    for (const auto& worker : samplesOfWorker) {
      figures.depthCompared += static_cast<std::int64_t>(worker[k].quanta.size());
      quanta.push_back(&worker[k].quanta);
      relative.push_back(&worker[k].relative);
      ratios.push_back(&worker[k].ratios);
    }
    allQuanta.insert(allQuanta.end(), quanta.begin(), quanta.end());
    allRelative.insert(allRelative.end(), relative.begin(), relative.end());
    allRatios.insert(allRatios.end(), ratios.begin(), ratios.end());
    jobs.push_back({std::move(quanta), &figures.depthErrorQuanta});
    jobs.push_back({std::move(relative), &figures.distanceRelError});
    jobs.push_back({std::move(ratios), &figures.toleranceRatio});
  }
  if (kindsWithSamples.size() > 1) {
    jobs.push_back({std::move(allQuanta), &total.depthErrorQuanta});
    jobs.push_back({std::move(allRelative), &total.distanceRelError});
    jobs.push_back({std::move(allRatios), &total.toleranceRatio});
  }
  parallelForRows(static_cast<int>(jobs.size()), threadCount, [&](int begin, int end) {
    for (int j = begin; j < end; ++j) *jobs[j].into = detail::distributionOfParts(jobs[j].parts);
  });
  if (kindsWithSamples.size() == 1) {
    total.depthErrorQuanta = total.byKind[0].depthErrorQuanta;
    total.distanceRelError = total.byKind[0].distanceRelError;
    total.toleranceRatio = total.byKind[0].toleranceRatio;
  }
  return result;
}

}  // namespace clipray

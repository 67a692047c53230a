#include "clipray/engine/WorstPixels.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

namespace {

SurfaceHit surfaceHit(const Scene& scene, const PrimitiveIdTable& table, std::uint32_t id,
                      double depth) {
  SurfaceHit hit;
  hit.id = id;
  if (id == 0) return hit;
  hit.depth = depth;
  const PrimitiveIdTable::Decoded decoded = table.decode(id);
  if (decoded.object >= 0) {
    hit.object = scene.objects[static_cast<std::size_t>(decoded.object)].name;
    hit.kind = "triangle";
    hit.triangle = decoded.triangle;
  } else if (decoded.analytic >= 0) {
    const AnalyticPrimitive& primitive =
        scene.primitives[static_cast<std::size_t>(decoded.analytic)];
    hit.object = primitive.name;
    hit.kind = primitiveKindName(primitive.kind);
  } else {
    hit.kind = "unknown";  // an id the scene lacks (an app's render function wrote it)
  }
  return hit;
}

int severity(PixelClass value) {
  switch (value) {
    case PixelClass::CoverageUnexplained:
    case PixelClass::IdUnexplained:
      return 0;
    case PixelClass::DepthBeyondTolerance:
      return 1;
    case PixelClass::Agree:
      return 2;
    default:
      return 3;  // ambiguous by the model, or background on both sides
  }
}

// Both sides at pixel i of the frames.
PixelHits pixelHits(const Scene& scene, const PrimitiveIdTable& table, const AnalyticPass& pass,
                    const RasterFrame& raster, const PixelComparison& pixels, std::size_t i) {
  const auto width = static_cast<std::size_t>(pixels.viewport.width);
  PixelHits hits;
  hits.x = static_cast<int>(i % width);
  hits.y = static_cast<int>(i / width);
  hits.pixelClass = pixels.classes[i];
  hits.raster = surfaceHit(scene, table, raster.ids[i], pixels.rasterDepth[i]);
  hits.ray = surfaceHit(scene, table, pass.frame.hits[i].primitiveId, pixels.analyticDepth[i]);
  hits.toleranceRatio = pixels.toleranceRatio[i];
  return hits;
}

// Orders pixels: unexplained classes first, then depths beyond tolerance, then agreeing pixels,
// then the rest; within each, the larger error / tolerance first (none last), then the lower index.
struct Worse {
  const PixelComparison& pixels;
  float ratio(std::size_t i) const {
    const float r = pixels.toleranceRatio[i];
    return std::isnan(r) ? -1.0f : r;
  }
  bool operator()(std::size_t a, std::size_t b) const {
    const int sa = severity(pixels.classes[a]), sb = severity(pixels.classes[b]);
    if (sa != sb) return sa < sb;
    if (ratio(a) != ratio(b)) return ratio(a) > ratio(b);
    return a < b;
  }
};

}  // namespace

std::vector<PixelReport> worstPixels(const AnalyticPass& pass, const RasterFrame& raster,
                                     const PixelComparison& pixels, std::size_t count,
                                     const std::optional<AppWindow>& window) {
  if (count == 0) return {};
  const std::size_t pixelCount = pixels.classes.size();
  std::vector<std::size_t> order;
  order.reserve(pixelCount);
  for (std::size_t i = 0; i < pixelCount; ++i) {
    if (pixels.classes[i] != PixelClass::Background) order.push_back(i);
  }
  const std::size_t keep = std::min(count, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(keep), order.end(),
                    Worse{pixels});
  order.resize(keep);

  const Scene& scene = *pass.scene;
  const PrimitiveIdTable table(scene);
  std::vector<PixelReport> reports;
  for (const std::size_t i : order) {
    const PixelHits hits = pixelHits(scene, table, pass, raster, pixels, i);
    PixelReport report;
    report.x = hits.x;
    report.y = hits.y;
    if (window) report.window = windowPositionOfPixel(*window, report.x, report.y, pixels.viewport);
    report.pixelClass = pixelClassName(hits.pixelClass);
    report.rasterHit = hits.raster.name();
    report.rayHit = hits.ray.name();
    report.rasterDepth = pixels.rasterDepth[i];
    report.rayDepth = pixels.analyticDepth[i];
    report.toleranceRatio = hits.toleranceRatio;
    reports.push_back(std::move(report));
  }
  return reports;
}

void describeHits(const AnalyticPass& pass, const RasterFrame& raster,
                  const PixelComparison& pixels, RunRecord& run) {
  const Scene& scene = *pass.scene;
  const PrimitiveIdTable table(scene);
  run.worstPixel.reset();
  run.clusterHits.clear();
  // Worse's first pixel in one pass over the frame, in pixel order: a pixel replaces the worst so
  // far only where it is strictly worse (ties keep the lower index), and its ratio is read only
  // where its class is as severe as the worst's.
  std::optional<std::size_t> worst;
  int worstSeverity = 4;  // above every class's
  float worstRatio = 0.0f;
  const Worse worse{pixels};
  for (std::size_t i = 0; i < pixels.classes.size(); ++i) {
    const PixelClass pixelClass = pixels.classes[i];
    if (pixelClass == PixelClass::Background) continue;
    const int s = severity(pixelClass);
    if (s > worstSeverity) continue;
    const float ratio = worse.ratio(i);
    if (s < worstSeverity || ratio > worstRatio) {
      worst = i;
      worstSeverity = s;
      worstRatio = ratio;
    }
  }
  if (worst) run.worstPixel = pixelHits(scene, table, pass, raster, pixels, *worst);
  const auto width = static_cast<std::size_t>(pixels.viewport.width);
  for (const MismatchCluster& cluster : run.clusters.largest) {
    const std::size_t i =
        static_cast<std::size_t>(cluster.y) * width + static_cast<std::size_t>(cluster.x);
    run.clusterHits.push_back(pixelHits(scene, table, pass, raster, pixels, i));
  }
}

}  // namespace clipray::engine

#include "clipray/engine/WorstPixels.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

namespace {

std::string hitName(const Scene& scene, const PrimitiveIdTable& table, std::uint32_t id) {
  if (id == 0) return "nothing";
  const PrimitiveIdTable::Decoded decoded = table.decode(id);
  if (decoded.object >= 0) {
    return "\"" + scene.objects[static_cast<std::size_t>(decoded.object)].name + "\" triangle " +
           std::to_string(decoded.triangle);
  }
  if (decoded.analytic >= 0) {
    const AnalyticPrimitive& primitive =
        scene.primitives[static_cast<std::size_t>(decoded.analytic)];
    return "\"" + primitive.name + "\" (" + primitiveKindName(primitive.kind) + ")";
  }
  return "id " + std::to_string(id);
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
  const auto ratio = [&](std::size_t i) {
    const float r = pixels.toleranceRatio[i];
    return std::isnan(r) ? -1.0f : r;
  };
  const auto worse = [&](std::size_t a, std::size_t b) {
    const int sa = severity(pixels.classes[a]), sb = severity(pixels.classes[b]);
    if (sa != sb) return sa < sb;
    if (ratio(a) != ratio(b)) return ratio(a) > ratio(b);
    return a < b;
  };
  const std::size_t keep = std::min(count, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(keep), order.end(),
                    worse);
  order.resize(keep);

  const Scene& scene = *pass.scene;
  const PrimitiveIdTable table(scene);
  const Viewport size = pixels.viewport;
  std::vector<PixelReport> reports;
  for (const std::size_t i : order) {
    PixelReport report;
    report.x = static_cast<int>(i % static_cast<std::size_t>(size.width));
    report.y = static_cast<int>(i / static_cast<std::size_t>(size.width));
    if (window) report.window = windowPositionOfPixel(*window, report.x, report.y, size);
    report.pixelClass = pixelClassName(pixels.classes[i]);
    report.rasterHit = hitName(scene, table, raster.ids[i]);
    report.rayHit = hitName(scene, table, pass.frame.hits[i].primitiveId);
    report.rasterDepth = pixels.rasterDepth[i];
    report.rayDepth = pixels.analyticDepth[i];
    report.toleranceRatio = pixels.toleranceRatio[i];
    reports.push_back(std::move(report));
  }
  return reports;
}

}  // namespace clipray::engine

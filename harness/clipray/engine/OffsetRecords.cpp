#include "clipray/engine/OffsetRecords.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clipray::engine {

std::vector<OffsetRecord> offsetRecords(const Scene& scene, const RasterFrame& raster,
                                        const AnalyticFrame& analytic,
                                        const PixelComparison& pixels,
                                        const ToleranceModel& model) {
  std::vector<OffsetRecord> records;
  std::vector<int> recordOfObject(scene.objects.size(), -1);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const MeshObject& object = scene.objects[k];
    if (!object.polygonOffset) continue;
    recordOfObject[k] = static_cast<int>(records.size());
    const PolygonOffset& o = *object.polygonOffset;
    records.push_back({object.name, o.factor, o.units, o.clamp, 0, kInf, -kInf, kInf, -kInf});
  }
  if (records.empty()) return records;
  const PrimitiveIdTable ids(scene);
  for (std::size_t i = 0; i < raster.ids.size(); ++i) {
    const std::uint32_t id = raster.ids[i];
    if (id == 0 || id >= ids.firstAnalyticId || id != analytic.hits[i].primitiveId) continue;
    // The object whose run of ids holds it: the last one starting at or before it.
    const auto object =
        std::upper_bound(ids.firstIdOfObject.begin(), ids.firstIdOfObject.end(), id);
    const std::size_t k = static_cast<std::size_t>(object - ids.firstIdOfObject.begin()) - 1;
    if (recordOfObject[k] < 0) continue;
    const double exact = pixels.analyticDepth[i];
    const double stored = raster.depth[i];
    if (!std::isfinite(exact) || !std::isfinite(stored)) continue;
    OffsetRecord& record = records[static_cast<std::size_t>(recordOfObject[k])];
    const OffsetInterval allowed = model.offsetInterval(id);
    ++record.pixels;
    record.predictedLow = std::min(record.predictedLow, allowed.low);
    record.predictedHigh = std::max(record.predictedHigh, allowed.high);
    record.measuredMin = std::min(record.measuredMin, stored - exact);
    record.measuredMax = std::max(record.measuredMax, stored - exact);
  }
  for (OffsetRecord& record : records) {
    if (record.pixels == 0)
      record.predictedLow = record.predictedHigh = record.measuredMin = record.measuredMax = 0.0;
  }
  return records;
}

}  // namespace clipray::engine

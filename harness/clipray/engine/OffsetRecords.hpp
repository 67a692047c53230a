#pragma once
// The report's polygon offsets (OffsetRecord, report/Report.hpp): per object drawn with one, the
// offsets GL allows its pixels beside those the raster stored.

#include <vector>

#include "clipray/compare/Frames.hpp"
#include "clipray/compare/Reconcile.hpp"
#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

// Over the pixels where the raster and the ray show the same primitive of an object with a
// polygon offset: the model's interval there (ToleranceModel::offsetInterval) and the measured
// offset, raster depth minus the exact depth of the hit (pixels.analyticDepth). None where no
// object has an offset.
std::vector<OffsetRecord> offsetRecords(const Scene& scene, const RasterFrame& raster,
                                        const AnalyticFrame& analytic,
                                        const PixelComparison& pixels, const ToleranceModel& model);

}  // namespace clipray::engine

#pragma once
// The pixels of a run worth describing to a person, as both sides saw them: what each side hit
// there (a named triangle or analytic primitive, or nothing) and at which window depth. The
// library's worst pixels (PixelReport), and the report's worst pixel and cluster pixels.

#include <cstddef>
#include <optional>
#include <vector>

#include "clipray/Picking.hpp"
#include "clipray/Reconcile.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/compare/Reconcile.hpp"
#include "clipray/engine/ReconcileRun.hpp"

namespace clipray::engine {

// At most `count` pixels of the run: unexplained coverage and id mismatches first, then depths
// beyond tolerance, then the rest; within each, the larger error / tolerance first (pixels without
// one last), then the lower index. Background pixels are left out. With a window, each pixel's
// centre is also given in its coordinates (windowPositionOfPixel).
std::vector<PixelReport> worstPixels(const AnalyticPass& pass, const RasterFrame& raster,
                                     const PixelComparison& pixels, std::size_t count,
                                     const std::optional<AppWindow>& window);

// What each side hit at the run's worst pixel (the first of worstPixels' order) and at each of
// its clusters' pixels: run.worstPixel (none where every pixel is background) and
// run.clusterHits, for the report.
void describeHits(const AnalyticPass& pass, const RasterFrame& raster,
                  const PixelComparison& pixels, RunRecord& run);

}  // namespace clipray::engine

#pragma once
// The one runner of a reconcile plan (ReconcilePlan.hpp), behind both `clipray reconcile` and
// clipray::reconcile: claims the output folder, loads the scenes within the memory budget, makes
// the GL context and checks the viewports against it, then makes every run (one analytic pass per
// scene camera and convention, shared by its depth formats and vertex modes), encodes the images
// beside the next runs, and writes the report. Every input error is thrown (InputError) before the
// first run; a failed run leaves nothing of its outputs behind.

#include <cstddef>
#include <vector>

#include "clipray/Reconcile.hpp"
#include "clipray/engine/ReconcilePlan.hpp"
#include "clipray/report/Report.hpp"

namespace clipray::engine {

struct ReconcileOutcome {
  // One record per run, in the plan's order (scene, camera, convention, depth format, vertex
  // mode); with several rounds, merged (mergeRounds). Their images are in them.
  std::vector<RunRecord> runs;
  // For each run, plan.worstPixelsPerRun of its pixels (WorstPixels.hpp).
  std::vector<std::vector<PixelReport>> worstPixels;
  GlInfo gl;  // the raster side's implementation
  bool consistent() const;
};

// Throws InputError for the inputs the plan could not check without the files or the GL
// implementation (scenes, viewports, the output folder), BackendError when the backend gives no
// context, std::runtime_error ("out of memory while ...") where the runs exhaust memory, and
// whatever the app's own render or picking functions throw.
ReconcileOutcome runReconcilePlan(const ReconcilePlan& plan);

}  // namespace clipray::engine

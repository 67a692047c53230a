#pragma once
// One reconcile, typed and checked, before anything runs: what `clipray reconcile` parses from its
// command line (cli/ReconcileCommand.cpp) and what clipray::reconcile takes from ReconcileOptions
// (Reconcile.cpp). runReconcilePlan (ReconcileRunner.hpp) executes it; both doors reach the same
// runs, the same report and the same images through it.
//
// A run is scene x camera x convention x depth format x vertex mode; the runs of one scene camera
// under one convention share one analytic pass (ReconcileRun.hpp).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "clipray/Conventions.hpp"
#include "clipray/Picking.hpp"
#include "clipray/Reconcile.hpp"
#include "clipray/engine/MemoryBudget.hpp"
#include "clipray/report/ImageEncoder.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/scene/Scene.hpp"
#include "clipray/util/AnalyticChoice.hpp"
#include "clipray/util/KernelChoice.hpp"

namespace clipray::engine {

// A scene of the plan: a file the runner loads (and may load again for its runs when the scenes do
// not all stay loaded within the memory budget), or one already in memory (a test's TestScene),
// which must outlive the run.
struct PlannedScene {
  std::string path;
  const Scene* loaded = nullptr;
};

// Shard `index` of `count` (1-based) of the scene/camera pairs, split by their names (shardOf).
struct Shard {
  int index = 1;
  int count = 1;
};
// The shard (1..count) a scene/camera pair belongs to: FNV-1a of the two names, so the split
// depends on nothing but the names, and adding scenes never moves the others between shards.
// Whole pairs, not single runs: a pair's runs share one analytic pass.
int shardOf(const std::string& scene, const std::string& camera, int count);

struct ReconcilePlan {
  // What runs.
  std::vector<PlannedScene> scenes;
  std::vector<std::string> cameras;  // by name, run in this order; empty: every camera
  // The conventions each camera is drawn under: these, else the scene's own list, else
  // defaultConventions (`clipray reconcile`: no, zo; the library: zo).
  std::vector<DepthMode> conventions;
  std::vector<DepthMode> defaultConventions;
  std::vector<DepthFormat> depthFormats;
  std::vector<VertexMode> vertexModes;
  std::optional<Viewport> size;  // every camera's viewport overridden
  std::string sizeOption;        // the field that set it, for messages ("--size")
  std::optional<Shard> shard;
  // Samples per pixel: above 1 every frame is drawn multisampled and each sample is a run of its
  // own, compared with rays through its position (MultisampleRun.hpp); clipray's renderer only,
  // and no picking hits.
  int samples = 0;                          // 0: each scene's own (Scene::samples)
  std::string samplesOption = "--samples";  // the field that set it, for messages

  // The raster side: clipray's renderer on `backend`, or the app's render function drawing into
  // clipray's framebuffer on that backend's context.
  std::string backend = "osmesa";
  AppRenderFunction appRender;
  AppIds appIds = AppIds::Written;
  // The app's window: the app's render function draws into a framebuffer of its size, and the
  // described pixels are named in its coordinates too.
  std::optional<AppWindow> window;
  // Where the RenderDoc captures of failing runs' app frames go (AppFrameCaptures.hpp); empty:
  // no capture.
  std::string renderDocCaptures;

  // The ray side: the app's picking function; empty: clipray's robust rays. Or the app's picking
  // with its own hits (pickHits, when set, in place of both).
  PickRayFunction pickRays;
  PickHitFunction pickHits;

  // How.
  MemoryBudget memory;                   // what the runs may take (MemoryBudget.hpp)
  std::optional<KernelChoice> kernels;   // chosen for the process before the runs; unset: as is
  std::optional<AnalyticPath> analytic;  // the same for the analytic path (AnalyticChoice.hpp)
  unsigned threads = 0;                  // for the analytic pass and the compare; 0: every core
  unsigned rounds = 1;                   // every run made this many times (mergeRounds)
  bool progress = false;                 // a progress line on stderr
  std::size_t worstPixelsPerRun = 0;     // pixels each run describes (ReconcileOutcome)

  // The outputs: nothing written where `out` is empty. Images under `images` (thumbnails for
  // index.html under any policy but none).
  std::string out;
  std::string outOption = "--out";  // the field that named it, for messages
  ImagePolicy images = ImagePolicy::Failing;
  std::string junit;  // also the runs as JUnit XML there; empty: none
  ReportProvenance provenance;
};

}  // namespace clipray::engine

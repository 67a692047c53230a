// clipray::reconcile (include/clipray/Reconcile.hpp): the library's door to the reconcile engine.
// ReconcileOptions become a plan (ReconcilePlan.hpp) that runReconcilePlan executes, as
// `clipray reconcile` does with its command line; the runs come back as RunResults.

#include "clipray/Reconcile.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "clipray/engine/ReconcilePlan.hpp"
#include "clipray/engine/ReconcileRunner.hpp"
#include "clipray/report/Report.hpp"

namespace clipray {

namespace {

void checkCameras(const Scene& scene, const ReconcileOptions& options) {
  for (const std::string& name : options.cameras) {
    const bool known = std::any_of(scene.cameras.begin(), scene.cameras.end(),
                                   [&](const Camera& camera) { return camera.name == name; });
    if (!known) {
      std::string names;
      for (const Camera& c : scene.cameras)
        names += (names.empty() ? "\"" : ", \"") + c.name + "\"";
      throw InputError("ReconcileOptions: cameras: no camera \"" + name + "\" in scene \"" +
                       scene.name + "\" (it has " + names + ")");
    }
  }
}

void checkOptions(const ReconcileOptions& options) {
  if (options.depthFormats.empty()) {
    throw InputError(
        "ReconcileOptions: depthFormats: expected at least one depth format, got none");
  }
  if (options.render && options.vertexMode != VertexMode::World) {
    throw InputError(
        "ReconcileOptions: vertexMode: the app's render function draws its own "
        "vertices; expected world, got " +
        vertexModeName(options.vertexMode));
  }
  if (!options.renderDocCaptures.empty() && !options.render) {
    throw InputError(
        "ReconcileOptions: renderDocCaptures: it captures the frames the app's render function "
        "draws; set render (clipray's own frames are drawn again by any reconcile)");
  }
}

engine::ReconcilePlan planOf(const Scene& scene, const PickRayFunction& pick,
                             const PickHitFunction& pickHits, const ReconcileOptions& options) {
  engine::ReconcilePlan plan;
  plan.scenes = {{scene.path, &scene}};
  // In the order named; a name given twice runs its camera once.
  plan.cameras = options.cameras;
  plan.conventions = options.conventions;
  plan.defaultConventions = {kZeroToOne};
  plan.depthFormats = options.depthFormats;
  plan.vertexModes = {options.vertexMode};
  plan.backend = options.backend;
  plan.appRender = options.render;
  plan.appIds = options.appIds;
  plan.window = options.window;
  plan.renderDocCaptures = options.renderDocCaptures;
  plan.pickRays = pick;
  plan.pickHits = pickHits;
  plan.memory = engine::machineMemoryBudget();
  plan.threads = options.threads;
  plan.samples = options.samples;
  plan.samplesOption = "ReconcileOptions: samples";
  plan.worstPixelsPerRun = options.worstPixels;
  plan.out = options.reportDirectory;
  plan.outOption = "ReconcileOptions: reportDirectory";
  plan.images = options.reportDirectory.empty()
                    ? ImagePolicy::None
                    : (options.imagesForEveryRun ? ImagePolicy::All : ImagePolicy::Failing);
  return plan;
}

bool isThumbnail(const EncodedImage& image) {
  return std::filesystem::path(image.relativePath).filename().string().rfind("thumb_", 0) == 0;
}

RunResult runResult(const RunRecord& run, const std::string& summaryLine, bool appRender) {
  RunResult result;
  result.scene = run.scene;
  result.camera = run.camera;
  result.convention = run.convention.name();
  result.depthFormat = depthFormatName(run.depthFormat);
  result.vertexMode = vertexModeName(run.vertexMode);
  result.appRender = appRender;
  result.size = run.size;
  if (run.sample) {
    result.sample = run.sample->index;
    result.sampleCount = run.sample->count;
    result.samplePosition = run.sample->position;
    result.framePartlyCoveredPixels = run.sample->pixels.partlyCovered;
    result.frameUnexplainedPixels = run.sample->pixels.unexplained;
  }
  const RunMetrics& m = run.metrics;
  result.verdict = runVerdictName(runVerdict(run));
  result.consistent = runPasses(run);
  for (const RunFinding& f : run.conventionFindings) {
    result.conventionFindings.push_back(f.severity + " [" + f.code + "] " + f.message +
                                        (f.expected ? " (expected by the scene)" : ""));
  }
  result.pixels = m.pixels;
  result.rasterHits = m.rasterHits;
  result.rayHits = m.rayHits;
  result.coverageMismatches = m.coverageMismatch.total;
  result.coverageUnexplained = m.coverageMismatch.unexplained;
  result.idMismatches = m.idMismatch.total;
  result.idUnexplained = m.idMismatch.unexplained;
  result.depthCompared = m.depthCompared;
  result.depthBeyondTolerance = m.depthBeyondTolerance;
  result.worstToleranceRatio = m.toleranceRatio.max;
  result.maxDepthErrorQuanta = m.depthErrorQuanta.max;
  result.maxDistanceRelError = m.distanceRelError.max;
  result.notes = run.notes;
  result.capture = run.capture;
  result.summaryLine = summaryLine + (appRender ? "  (app render)" : "");
  return result;
}

}  // namespace

namespace {

ReconcileResult reconcilePicks(const TestScene& testScene, const PickRayFunction& pick,
                               const PickHitFunction& pickHits, const ReconcileOptions& options) {
  checkOptions(options);
  const Scene& scene = testScene.model();
  checkCameras(scene, options);
  engine::ReconcileOutcome outcome =
      engine::runReconcilePlan(planOf(scene, pick, pickHits, options));

  ReconcileResult result;
  // The runs' summary lines in one set of columns, as ReconcileResult::text prints them together.
  const std::vector<std::string> summaryLines = runSummaryLines(outcome.runs);
  for (std::size_t r = 0; r < outcome.runs.size(); ++r) {
    const RunRecord& record = outcome.runs[r];
    RunResult run = runResult(record, summaryLines[r], static_cast<bool>(options.render));
    run.worstPixels = std::move(outcome.worstPixels[r]);
    // The images a person opens (the four full-size PNGs and the cluster crops), not the
    // thumbnails of index.html.
    for (const EncodedImage& image : record.images) {
      if (isThumbnail(image)) continue;
      run.images.push_back(
          (std::filesystem::path(options.reportDirectory) / image.relativePath).string());
    }
    result.runs.push_back(std::move(run));
  }
  result.reportDirectory = options.reportDirectory;
  return result;
}

}  // namespace

ReconcileResult reconcile(const TestScene& scene, const PickRayFunction& pick,
                          const ReconcileOptions& options) {
  return reconcilePicks(scene, pick, {}, options);
}

ReconcileResult reconcile(const TestScene& scene, const PickHitFunction& pick,
                          const ReconcileOptions& options) {
  return reconcilePicks(scene, {}, pick, options);
}

bool ReconcileResult::consistent() const {
  return std::all_of(runs.begin(), runs.end(), [](const RunResult& run) { return run.consistent; });
}

std::string PixelReport::text() const {
  std::ostringstream out;
  out << "pixel (" << x << ", " << y << ")";
  if (window) out << " window (" << window->x << ", " << window->y << ")";
  out << " " << pixelClass << ": raster " << rasterHit;
  if (!std::isnan(rasterDepth)) out << " at depth " << shortNumber(rasterDepth);
  out << ", ray " << rayHit;
  if (!std::isnan(rayDepth)) out << " at depth " << shortNumber(rayDepth);
  if (!std::isnan(toleranceRatio)) out << ", error/tolerance " << shortNumber(toleranceRatio);
  return out.str();
}

std::string ReconcileResult::text() const {
  std::string out;
  std::size_t inconsistent = 0, conventionErrors = 0;
  for (const RunResult& run : runs) {
    out += run.summaryLine + "\n";
    inconsistent += run.verdict == "inconsistent" ? 1 : 0;
    conventionErrors += run.verdict == "convention-error" ? 1 : 0;
  }
  for (const RunResult& run : runs) {
    if (run.conventionFindings.empty()) continue;
    out += run.scene + "/" + run.camera + " " + run.convention + " " + run.depthFormat +
           ": the convention check of the camera under the run's state\n";
    for (const std::string& finding : run.conventionFindings) out += "  " + finding + "\n";
  }
  for (const RunResult& run : runs) {
    if (run.notes.empty()) continue;
    out += run.scene + "/" + run.camera + " " + run.convention + " " + run.depthFormat +
           ": the app's GL state\n";
    for (const std::string& note : run.notes) out += "  " + note + "\n";
  }
  for (const RunResult& run : runs) {
    if (run.verdict != "inconsistent") continue;
    out += run.scene + "/" + run.camera + " " + run.convention + " " + run.depthFormat +
           ": worst pixels\n";
    for (const PixelReport& pixel : run.worstPixels) out += "  " + pixel.text() + "\n";
    for (const std::string& image : run.images) out += "  image " + image + "\n";
  }
  for (const RunResult& run : runs) {
    if (run.capture.empty()) continue;
    out += run.scene + "/" + run.camera + " " + run.convention + " " + run.depthFormat +
           ": the app's frame, captured by RenderDoc: " + run.capture + "\n";
  }
  out += std::to_string(runs.size()) +
         " runs: " + std::to_string(runs.size() - inconsistent - conventionErrors) +
         " consistent, " + std::to_string(inconsistent) + " inconsistent";
  if (conventionErrors > 0) out += ", " + std::to_string(conventionErrors) + " convention errors";
  if (!reportDirectory.empty()) out += "; report " + reportDirectory + "/index.html";
  return out + "\n";
}

}  // namespace clipray

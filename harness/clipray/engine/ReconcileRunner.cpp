#include "clipray/engine/ReconcileRunner.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "clipray/InputError.hpp"
#include "clipray/compare/DrawCallIds.hpp"
#include "clipray/engine/AppFrameCaptures.hpp"
#include "clipray/engine/AppStateNotes.hpp"
#include "clipray/engine/MultisampleRun.hpp"
#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/engine/RunConventionCheck.hpp"
#include "clipray/engine/WorstPixels.hpp"
#include "clipray/gl/AppRender.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/io/OutputFolder.hpp"
#include "clipray/report/ImageEncoder.hpp"
#include "clipray/report/JUnit.hpp"

namespace clipray::engine {

bool ReconcileOutcome::consistent() const {
  return std::all_of(runs.begin(), runs.end(), runPasses);
}

int shardOf(const std::string& scene, const std::string& camera, int count) {
  std::uint64_t hash = 14695981039346656037ull;
  const auto mix = [&](const std::string& text) {
    for (const unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
    hash = (hash ^ 0xffu) * 1099511628211ull;  // a separator no name contains
  };
  mix(scene);
  mix(camera);
  return static_cast<int>(hash % static_cast<std::uint64_t>(count)) + 1;
}

namespace {

std::string sizeText(Viewport v) {
  return std::to_string(v.width) + "x" + std::to_string(v.height);
}

// The plan's scenes, loaded: those that fit stay loaded between their runs; the others keep their
// names, cameras and conventions and are loaded again for their runs.
struct LoadedScenes {
  std::vector<Scene> owned;          // loaded from files, in plan order (with `loaded` null)
  std::vector<const Scene*> scenes;  // every scene, in plan order
  std::vector<bool> loadForItsRuns;  // the geometry was dropped: load it again to run it
  std::vector<std::string> paths;    // where to load it again from
};

class Runner {
 public:
  explicit Runner(const ReconcilePlan& plan) : plan_(plan) {}

  ReconcileOutcome run() {
    step_ = "checking the options";
    try {
      return runSteps();
    } catch (const std::bad_alloc&) {
      throw std::runtime_error("out of memory while " + step_ +
                               "; try a smaller --size, fewer scenes, or --max-memory below what "
                               "the machine has");
    }
  }

 private:
  ReconcileOutcome runSteps();
  void loadScenes();
  void checkViewports(const gl::Renderer& renderer) const;
  // A sample count above 1: one the implementation offers for every depth format, with clipray's
  // renderer and rays.
  void checkSamples(gl::Renderer& renderer) const;
  // The samples per pixel a scene's runs are drawn with: the plan's, else the scene's own; and the
  // field that set it, for messages.
  int samplesOf(const Scene& scene) const;
  std::string samplesField(const Scene& scene) const;
  void runCamera(unsigned round, const Scene& scene, const Camera& camera, gl::GlContext& context,
                 gl::Renderer& renderer, std::vector<RunRecord>& runs);
  // The same, multisampled: a run per sample (MultisampleRun.hpp).
  void runCameraSampled(unsigned round, const Scene& scene, const Camera& camera,
                        gl::GlContext& context, gl::Renderer& renderer,
                        std::vector<RunRecord>& runs);
  // A compared run's outputs: its hits described, worst pixels and images in the last round.
  void keepRun(bool lastRound, const engine::AnalyticPass& pass, const RasterFrame& raster,
               engine::ComparedRun compared, std::vector<RunRecord>& runs);
  // The app's frame (every sample of it where `samples` is above 1), and the notes on the state
  // its draws were made with (AppStateNotes.hpp). `drawnCamera` is the camera as drawn, unsheared.
  gl::AppRaster drawWithApp(gl::GlContext& context, const Scene& scene, const Camera& camera,
                            const engine::AnalyticPass& pass, const PickingCamera& drawnCamera,
                            DepthFormat format, int samples, gl::RenderTimings& timings,
                            std::vector<std::string>& notes) const;
  std::vector<DepthMode> conventionsOf(const Scene& scene) const;
  // The scene's cameras the plan runs: those it names, in its order, else all; within the shard.
  std::vector<const Camera*> camerasOf(const Scene& scene) const;

  const ReconcilePlan& plan_;
  std::string step_;  // what the run is doing, for the one line an exhausted memory gets
  LoadedScenes loaded_;
  ImageEncoder encoder_;
  std::vector<std::vector<PixelReport>> worstPixels_;
  // With ReconcilePlan::renderDocCaptures and the app's render function.
  std::unique_ptr<AppFrameCaptures> captures_;
};

void Runner::loadScenes() {
  // The memory a run may take: its pixels and its scene's triangles (MemoryBudget.hpp). Scenes
  // stay loaded between their runs while they fit beside the largest run in half the budget;
  // past that, a scene's geometry is dropped once it is checked and loaded again for its runs.
  const double budget = plan_.memory.bytes;
  double keptBytes = 0.0;
  loaded_.owned.reserve(plan_.scenes.size());
  for (const PlannedScene& planned : plan_.scenes) {
    Scene* owned = nullptr;
    if (!planned.loaded) {
      step_ = "loading " + planned.path;
      owned = &loaded_.owned.emplace_back(loadScene(planned.path));
      // What the loaders kept but flagged (degenerate triangles, ...): worth seeing, not fatal.
      for (const std::string& warning : owned->warnings) {
        std::cerr << "clipray: warning: " << warning << "\n";
      }
    }
    const Scene& scene = owned ? *owned : *planned.loaded;
    loaded_.scenes.push_back(&scene);
    loaded_.paths.push_back(owned ? planned.path : scene.path);
    const double triangles = static_cast<double>(scene.triangleCount());
    double pixels = 0.0;
    for (const Camera& camera : scene.cameras) {
      const Viewport v = plan_.size.value_or(camera.viewport);
      pixels = std::max(pixels, static_cast<double>(v.width) * v.height);
    }
    const double runBytes =
        kRunBytesPerTriangle * triangles + runBytesPerPixel(samplesOf(scene)) * pixels;
    if (budget > 0.0 && runBytes > budget) {
      throw InputError(loaded_.paths.back() + ": one run needs about " + memoryText(runBytes) +
                       " (" + std::to_string(scene.triangleCount()) + " triangles, " +
                       std::to_string(static_cast<long long>(pixels)) + " pixels); " +
                       plan_.memory.text);
    }
    // A scene handed over in memory stays where it is; only a loaded one can be dropped.
    const double loadedBytes = kLoadedBytesPerTriangle * triangles;
    const bool keep = !owned || budget <= 0.0 || keptBytes + loadedBytes + runBytes <= budget / 2.0;
    loaded_.loadForItsRuns.push_back(!keep);
    if (keep) {
      keptBytes += loadedBytes;
    } else {
      std::cerr << "clipray: note: " << planned.path << " (" << scene.triangleCount()
                << " triangles) is loaded again for its runs: the scenes do not all stay loaded "
                   "beside a run where "
                << plan_.memory.text << "\n";
      owned->objects = {};  // names, cameras and conventions stay for the checks below
    }
  }
  // Runs are filed under their scene's and camera's names: no two may share a folder.
  checkDistinctRunFolders(loaded_.scenes);
}

// The limits only the GL implementation knows.
void Runner::checkViewports(const gl::Renderer& renderer) const {
  const Viewport maxViewport = renderer.maxViewport();
  auto checkViewport = [&](Viewport v, int samples, const std::string& where) {
    if (v.width > maxViewport.width || v.height > maxViewport.height) {
      throw InputError(where + ": " + sizeText(v) + " exceeds GL_MAX_VIEWPORT_DIMS " +
                       sizeText(maxViewport) + " of " + renderer.info().renderer);
    }
    const double needed = runBytesPerPixel(samples) * v.width * v.height;
    if (plan_.memory.bytes > 0.0 && needed > plan_.memory.bytes) {
      throw InputError(where + ": " + sizeText(v) + " needs about " + memoryText(needed) +
                       " of memory for one run; " + plan_.memory.text);
    }
  };
  if (plan_.size) {
    int samples = 1;
    for (const Scene* scene : loaded_.scenes) samples = std::max(samples, samplesOf(*scene));
    checkViewport(*plan_.size, samples, plan_.sizeOption);
    return;
  }
  for (const Scene* scene : loaded_.scenes) {
    for (std::size_t c = 0; c < scene->cameras.size(); ++c) {
      checkViewport(scene->cameras[c].viewport, samplesOf(*scene),
                    scene->path + ": /cameras/" + std::to_string(c) + "/viewport");
    }
  }
}

std::vector<DepthMode> Runner::conventionsOf(const Scene& scene) const {
  if (!plan_.conventions.empty()) return plan_.conventions;
  return scene.conventions.empty() ? plan_.defaultConventions : scene.conventions;
}

std::vector<const Camera*> Runner::camerasOf(const Scene& scene) const {
  std::vector<const Camera*> cameras;
  const auto add = [&](const Camera& camera) {
    if (std::find(cameras.begin(), cameras.end(), &camera) != cameras.end()) return;
    if (plan_.shard && shardOf(scene.name, camera.name, plan_.shard->count) != plan_.shard->index) {
      return;
    }
    cameras.push_back(&camera);
  };
  if (plan_.cameras.empty()) {
    for (const Camera& camera : scene.cameras) add(camera);
    return cameras;
  }
  for (const std::string& name : plan_.cameras) {
    for (const Camera& camera : scene.cameras) {
      if (camera.name == name) add(camera);
    }
  }
  return cameras;
}

// The raster side drawn by the app's render function into a framebuffer of its window's size.
gl::AppRaster Runner::drawWithApp(gl::GlContext& context, const Scene& scene, const Camera& camera,
                                  const engine::AnalyticPass& pass,
                                  const PickingCamera& drawnCamera, DepthFormat format, int samples,
                                  gl::RenderTimings& timings,
                                  std::vector<std::string>& notes) const {
  const Viewport viewport = pass.camera.viewport;
  AppFrame frame;
  frame.size = viewport;
  frame.viewport = {0, 0, viewport.width, viewport.height};
  if (plan_.window) {
    const AppWindow& window = *plan_.window;
    frame.viewport.x = window.viewportX;
    frame.viewport.y = window.viewportY;
    frame.size.width =
        window.framebufferWidth != 0 ? window.framebufferWidth : window.viewportX + viewport.width;
    frame.size.height = window.framebufferHeight != 0 ? window.framebufferHeight
                                                      : window.viewportY + viewport.height;
    if (frame.size.width < frame.viewport.x + frame.viewport.z ||
        frame.size.height < frame.viewport.y + frame.viewport.w) {
      throw InputError("ReconcileOptions: window: a " + sizeText(frame.size) +
                       " framebuffer cannot hold camera \"" + camera.name + "\"'s " +
                       std::to_string(frame.viewport.z) + "x" + std::to_string(frame.viewport.w) +
                       " viewport at (" + std::to_string(frame.viewport.x) + ", " +
                       std::to_string(frame.viewport.y) + ")");
    }
  }
  frame.camera = drawnCamera;
  frame.depthFormat = format;
  frame.samples = samples;
  frame.firstIds = PrimitiveIdTable(scene).firstIdOfObject;
  if (captures_) captures_->start();
  gl::AppRaster drawn =
      gl::renderWithApp(context, plan_.appRender, std::move(frame), plan_.appIds, scene, &timings);
  if (captures_) captures_->end();
  if (plan_.appIds == AppIds::PerDrawCall) {
    drawn.frame.ids = idsFromDrawCalls(scene, pass.camera, drawn.meshOfPixel, pass.frame);
  }
  notes = appStateNotes(drawn.draws, drawnCamera.mode, scene, plan_.appIds);
  return drawn;
}

// One scene camera: an analytic pass per convention, shared by its depth formats and vertex modes.
void Runner::runCamera(unsigned round, const Scene& scene, const Camera& camera,
                       gl::GlContext& context, gl::Renderer& renderer,
                       std::vector<RunRecord>& runs) {
  if (samplesOf(scene) > 1) {
    runCameraSampled(round, scene, camera, context, renderer, runs);
    return;
  }
  const bool lastRound = round == plan_.rounds;
  const Viewport viewport = plan_.size.value_or(camera.viewport);
  for (const DepthMode mode : conventionsOf(scene)) {
    step_ = "tracing " + scene.name + "/" + camera.name + " " + mode.name() + " at " +
            sizeText(viewport);
    const engine::AnalyticPass pass =
        plan_.pickHits
            ? engine::runAnalyticPass(scene, camera, mode, viewport, plan_.pickHits, plan_.threads)
        : plan_.pickRays
            ? engine::runAnalyticPass(scene, camera, mode, viewport, plan_.pickRays, plan_.threads)
            : engine::runAnalyticPass(scene, camera, mode, viewport, plan_.threads);
    for (const DepthFormat format : plan_.depthFormats) {
      // The camera's matrix under the state these runs are drawn with (the vertex mode changes
      // what is uploaded, not the matrix the app means).
      const std::vector<RunFinding> conventionFindings = runConventionFindings(
          scene, camera, pass.drawnCamera.clipFromWorld, mode, viewport, format);
      for (const VertexMode vertexMode : plan_.vertexModes) {
        if (plan_.progress) {
          std::cerr << "clipray: ";
          if (plan_.rounds > 1) std::cerr << "round " << round << "/" << plan_.rounds << " ";
          std::cerr << scene.name << "/" << camera.name << " " << mode.name() << " "
                    << depthFormatName(format) << " " << vertexModeName(vertexMode) << "\x1b[K\r"
                    << std::flush;
        }
        step_ = "running " + scene.name + "/" + camera.name + " " + mode.name() + " " +
                depthFormatName(format) + " " + vertexModeName(vertexMode);
        gl::RenderTimings timings;
        RasterFrame raster;
        std::vector<std::string> notes;
        if (plan_.appRender) {
          raster =
              drawWithApp(context, scene, camera, pass, pass.drawnCamera, format, 1, timings, notes)
                  .frame;
        } else {
          raster = renderer.render(renderRequest(pass, format, vertexMode), &timings);
        }
        engine::ComparedRun compared = engine::compareRasterFrame(
            pass, raster, format, vertexMode, renderer.info().subpixelBits, timings, plan_.threads);
        compared.run.notes = std::move(notes);
        compared.run.notes.insert(compared.run.notes.end(), pass.pickNotes.begin(),
                                  pass.pickNotes.end());
        compared.run.conventionFindings = conventionFindings;
        if (plan_.appRender && captures_) {
          RunRecord* const frameRuns[] = {&compared.run};
          captures_->settle(frameRuns);
        }
        keepRun(lastRound, pass, raster, std::move(compared), runs);
      }
    }
  }
}

void Runner::keepRun(bool lastRound, const engine::AnalyticPass& pass, const RasterFrame& raster,
                     engine::ComparedRun compared, std::vector<RunRecord>& runs) {
  describeHits(pass, raster, compared.pixels, compared.run);
  if (lastRound) {
    worstPixels_.push_back(
        worstPixels(pass, raster, compared.pixels, plan_.worstPixelsPerRun, plan_.window));
    if (wantsThumbnails(plan_.images)) {
      encoder_.submit(runs.size(), compared.run, std::move(compared.pixels),
                      wantsImages(plan_.images, compared.run.metrics));
    }
  }
  runs.push_back(std::move(compared.run));
}

int Runner::samplesOf(const Scene& scene) const {
  return plan_.samples > 0 ? plan_.samples : scene.samples;
}

std::string Runner::samplesField(const Scene& scene) const {
  return plan_.samples > 0 ? plan_.samplesOption + " " + std::to_string(plan_.samples)
                           : scene.path + ": /samples " + std::to_string(scene.samples);
}

void Runner::checkSamples(gl::Renderer& renderer) const {
  if (plan_.samples < 0) {
    throw InputError(plan_.samplesOption + " " + std::to_string(plan_.samples) +
                     ": expected a sample count of 1 or more (0: each scene's own)");
  }
  for (const Scene* scene : loaded_.scenes) {
    const int samples = samplesOf(*scene);
    if (samples == 1) continue;
    const std::string field = samplesField(*scene);
    if (plan_.appRender && plan_.appIds == AppIds::PerDrawCall) {
      throw InputError(field +
                       ": one id per draw call (AppIds::PerDrawCall) is read from the stencil "
                       "buffer, one value per pixel; a multisampled app frame needs its ids "
                       "written per fragment (AppIds::Written)");
    }
    for (const DepthFormat format : plan_.depthFormats) {
      const std::vector<int> offered = renderer.sampleCounts(format);
      if (std::find(offered.begin(), offered.end(), samples) == offered.end()) {
        std::string counts;
        for (const int n : offered) counts += (counts.empty() ? "" : ", ") + std::to_string(n);
        throw InputError(field + ": " + renderer.info().backend + " (" + renderer.info().renderer +
                         ") offers no " + std::to_string(samples) + "-sample depth format " +
                         depthFormatName(format) + " (it offers " +
                         (counts.empty() ? "no multisampling" : counts) + ")");
      }
    }
  }
}

void Runner::runCameraSampled(unsigned round, const Scene& scene, const Camera& camera,
                              gl::GlContext& context, gl::Renderer& renderer,
                              std::vector<RunRecord>& runs) {
  const int samples = samplesOf(scene);
  if (!scene.primitives.empty()) {
    throw InputError(samplesField(scene) + ": scene \"" + scene.name + "\" (" + scene.path +
                     ") has analytic primitives, which are drawn with one depth per pixel "
                     "(gl_FragDepth at its centre); multisampled runs need triangle meshes only");
  }
  if (camera.logarithmicDepth) {
    throw InputError(samplesField(scene) + ": camera \"" + camera.name + "\" of scene \"" +
                     scene.name + "\" (" + scene.path +
                     ") draws a logarithmic depth, written by the shader once per pixel "
                     "(gl_FragDepth at its centre); multisampled runs need the projective depth");
  }
  const bool lastRound = round == plan_.rounds;
  const Viewport viewport = plan_.size.value_or(camera.viewport);
  for (const DepthMode mode : conventionsOf(scene)) {
    step_ = "tracing " + scene.name + "/" + camera.name + " " + mode.name() + " at " +
            sizeText(viewport) + " for " + std::to_string(samples) + " samples";
    engine::MultisampleCamera sampled(scene, camera, mode, viewport, plan_.threads, plan_.pickRays,
                                      plan_.pickHits);
    for (const DepthFormat format : plan_.depthFormats) {
      const std::vector<RunFinding> conventionFindings = runConventionFindings(
          scene, camera, sampled.drawnClipFromWorld(), mode, viewport, format);
      for (const VertexMode vertexMode : plan_.vertexModes) {
        step_ = "running " + scene.name + "/" + camera.name + " " + mode.name() + " " +
                depthFormatName(format) + " " + vertexModeName(vertexMode) + " at " +
                std::to_string(samples) + " samples";
        std::vector<std::string> notes;
        engine::SampleComparison sampledRun;
        if (plan_.appRender) {
          // The passes for the positions the renderer reports, whose drawn camera (unsheared) the
          // app is handed; compared at the positions the app's framebuffer reports.
          const engine::AnalyticPass& first =
              sampled.passesAt(renderer.samplePositions(format, samples, viewport)).front();
          PickingCamera drawnCamera = first.drawnCamera;
          drawnCamera.clipFromWorld = sampled.drawnClipFromWorld();
          gl::RenderTimings timings;
          gl::AppRaster drawn = drawWithApp(context, scene, camera, first, drawnCamera, format,
                                            samples, timings, notes);
          sampledRun =
              sampled.compareSamples(std::move(drawn.samples), drawn.samplePositions, format,
                                     vertexMode, renderer.info().subpixelBits, timings);
        } else {
          sampledRun = sampled.rasterAndCompare(renderer, format, vertexMode, samples);
        }
        const std::vector<engine::AnalyticPass>& passes = sampled.passesAt(sampledRun.positions);
        std::vector<RunRecord*> frameRuns;
        for (std::size_t s = 0; s < sampledRun.samples.size(); ++s) {
          sampledRun.samples[s].run.conventionFindings = conventionFindings;
          sampledRun.samples[s].run.notes = notes;
          sampledRun.samples[s].run.notes.insert(sampledRun.samples[s].run.notes.end(),
                                                 passes[s].pickNotes.begin(),
                                                 passes[s].pickNotes.end());
          frameRuns.push_back(&sampledRun.samples[s].run);
        }
        if (plan_.appRender && captures_) captures_->settle(frameRuns);
        for (std::size_t s = 0; s < sampledRun.samples.size(); ++s) {
          keepRun(lastRound, passes[s], sampledRun.rasters[s], std::move(sampledRun.samples[s]),
                  runs);
        }
      }
    }
  }
}

ReconcileOutcome Runner::runSteps() {
  if (plan_.kernels) chooseKernels(*plan_.kernels);
  if (plan_.analytic) chooseAnalyticPath(*plan_.analytic);

  // The output folder is claimed before any work is done (it is written only at the end): created,
  // proven writable and locked against a second run writing into it at the same time. Whatever
  // fails from here on leaves nothing behind of this run's.
  std::optional<OutputFolder> out;
  if (!plan_.out.empty()) {
    out.emplace(plan_.out, plan_.outOption);
    if (out->recoveredInterruptedWrite()) {
      std::cerr << "clipray: warning: " << plan_.outOption << " " << plan_.out
                << ": a run was killed while writing its report there; the previous report is "
                   "back in place\n";
    }
  }
  loadScenes();

  // The backend, and the limits only it knows.
  const std::unique_ptr<gl::GlContext> context = gl::createContext(plan_.backend);
  gl::Renderer renderer(*context);  // loads GL and checks for 4.5 (glClipControl)
  checkViewports(renderer);
  checkSamples(renderer);
  if (plan_.appRender && !plan_.renderDocCaptures.empty()) {
    captures_ = std::make_unique<AppFrameCaptures>(plan_.renderDocCaptures);
  }

  // The runs, round after round (images in the last round only), encoded on worker threads
  // beside the next runs.
  std::vector<std::vector<RunRecord>> rounds;
  for (unsigned round = 1; round <= plan_.rounds; ++round) {
    std::vector<RunRecord>& runs = rounds.emplace_back();
    for (std::size_t s = 0; s < loaded_.scenes.size(); ++s) {
      std::optional<Scene> loadedAgain;
      step_ = "loading " + loaded_.paths[s];
      if (loaded_.loadForItsRuns[s]) loadedAgain.emplace(loadScene(loaded_.paths[s]));
      const Scene& scene = loadedAgain ? *loadedAgain : *loaded_.scenes[s];
      for (const Camera* camera : camerasOf(scene)) {
        runCamera(round, scene, *camera, *context, renderer, runs);
      }
    }
  }
  if (plan_.progress) std::cerr << "\x1b[K" << std::flush;
  ReconcileOutcome outcome;
  // One record per run, the last round's: the same order as the keys the encoder was given.
  outcome.runs = mergeRounds(std::move(rounds));
  encoder_.collect(outcome.runs);
  outcome.worstPixels = std::move(worstPixels_);
  outcome.gl = renderer.info();

  // Outputs, all at the end and each atomically.
  if (out) {
    step_ = "writing the report into " + plan_.out;
    writeReport(plan_.out, outcome.runs, outcome.gl, plan_.provenance);
    out->commit();
  }
  if (!plan_.junit.empty()) writeFileAtomically(plan_.junit, junitXml(outcome.runs, plan_.out));
  return outcome;
}

}  // namespace

ReconcileOutcome runReconcilePlan(const ReconcilePlan& plan) {
  return Runner(plan).run();
}

}  // namespace clipray::engine

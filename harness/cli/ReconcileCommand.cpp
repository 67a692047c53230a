// `clipray reconcile`: rasterize every scene headlessly, trace the same pixels analytically,
// compare.

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <new>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "Commands.hpp"
#include "MemoryBudget.hpp"
#include "clipray/InputError.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/ReconcileRun.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/report/ImageEncoder.hpp"
#include "clipray/report/JUnit.hpp"
#include "clipray/report/OutputFolder.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/scene/Scene.hpp"
#include "clipray/util/KernelChoice.hpp"
#include "clipray/util/OptionValues.hpp"

namespace clipray::cli {

namespace {

template <typename T, typename Parse>
std::vector<T> parseList(const std::string& option, const std::string& text, Parse parse,
                         const std::string& valid) {
  std::vector<T> values;
  for (const std::string& item : splitCommaList(text)) {
    const std::optional<T> value = parse(item);
    if (!value) {
      throw InputError(option + ": unknown value \"" + item +
                       "\"; expected a comma-separated list of: " + valid);
    }
    if (std::find(values.begin(), values.end(), *value) == values.end()) values.push_back(*value);
  }
  if (values.empty()) throw InputError(option + ": expected at least one of: " + valid);
  return values;
}

struct ReconcileOptions {
  std::vector<std::string> scenes;
  std::string backend = "osmesa";
  std::string conventions;  // empty: per scene, default no,zo
  std::string depthFormats = "24,32f";
  std::string vertexModes = "world";
  std::string size;
  std::string out = "report";
  std::string images = "failing";
  std::string kernels = "simd";
  std::string junit;  // empty: no JUnit file
  bool json = false;
  unsigned threads = 0;
  unsigned rounds = 1;
  std::string maxMemory;        // empty: what the machine (or the cgroup) has available
  std::string shard;            // "I/N": only the scene/camera pairs of shard I of N
  ReportProvenance provenance;  // the command line and start time, for report.json
};

// "I/N" with 1 <= I <= N <= 100000 (a CI matrix of any size); throws InputError otherwise.
std::pair<int, int> parseShard(const std::string& text) {
  int index = 0, count = 0;
  char slash = 0;
  std::istringstream stream(text);
  if (!(stream >> index >> slash >> count) || slash != '/' || !stream.eof() || index < 1 ||
      count < 1 || index > count || count > 100000) {
    throw InputError(
        "--shard: expected I/N with 1 <= I <= N (e.g. 2/8 for the second of eight "
        "jobs), got \"" +
        text + "\"");
  }
  return {index, count};
}

// The shard (1..count) a scene/camera pair belongs to: FNV-1a of the two names, so the split
// depends on nothing but the names, and adding scenes never moves the others between shards.
// Whole pairs, not single runs: a pair's runs share one analytic pass.
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

// What the run is doing, for the one line an exhausted memory gets ("out of memory while ...").
std::string& currentStep() {
  static std::string step;
  return step;
}

int runReconcileSteps(const ReconcileOptions& options) {
  // 1. Everything the user handed us is checked before anything is rendered or written.
  const std::vector<DepthFormat> formats = parseList<DepthFormat>(
      "--depth-formats", options.depthFormats, parseDepthFormat, "16, 24, 32f");
  const std::vector<VertexMode> vertexModes =
      parseList<VertexMode>("--vertex-modes", options.vertexModes, parseVertexMode,
                            "world, camera-relative, pretransformed");
  const std::optional<ImagePolicy> imagePolicy = parseImagePolicy(options.images);
  if (!imagePolicy) {
    throw InputError("--images: unknown value \"" + options.images +
                     "\"; expected one of: failing, all, none");
  }
  if (options.kernels != "simd" && options.kernels != "portable") {
    throw InputError("--kernels: unknown value \"" + options.kernels +
                     "\"; expected one of: simd, portable");
  }
  chooseKernels(options.kernels == "simd" ? KernelChoice::Simd : KernelChoice::Portable);
  std::optional<std::vector<DepthMode>> conventions;
  if (!options.conventions.empty()) {
    conventions = parseList<DepthMode>("--conventions", options.conventions, DepthMode::parse,
                                       "no, zo, zo-reversed");
  }
  std::optional<std::pair<int, int>> shard;
  if (!options.shard.empty()) shard = parseShard(options.shard);
  ReportProvenance provenance = options.provenance;
  if (shard) std::tie(provenance.shardIndex, provenance.shardCount) = *shard;
  const std::optional<Viewport> sizeOverride =
      options.size.empty() ? std::nullopt
                           : std::optional<Viewport>(parseViewportOption(options.size, "--size"));

  if (!options.junit.empty()) {
    const std::filesystem::path junit(options.junit);
    const std::filesystem::path folder =
        junit.has_parent_path() ? junit.parent_path() : std::filesystem::path(".");
    if (std::filesystem::is_directory(junit)) {
      throw InputError("--junit: " + options.junit + " is a folder; name the XML file to write");
    }
    if (!std::filesystem::is_directory(folder)) {
      throw InputError("--junit: " + options.junit + ": the folder " + folder.string() +
                       " does not exist");
    }
  }

  // The output folder is claimed before any work is done (it is written only at the end): created,
  // proven writable and locked against a second run writing into it at the same time. Whatever
  // fails from here on leaves nothing behind of this run's.
  OutputFolder out(options.out);
  if (out.recoveredInterruptedWrite()) {
    std::cerr << "clipray: warning: --out " << options.out
              << ": a run was killed while writing its report there; the previous report is "
                 "back in place\n";
  }

  std::vector<std::string> scenePaths = options.scenes;
  if (scenePaths.empty()) {
    if (!std::filesystem::is_directory("scenes")) {
      throw InputError(
          "no scene given and there is no scenes/ folder here; name scene files, e.g. clipray "
          "reconcile scenes/standard.json");
    }
    // Scene files only: the mesh files under scenes/assets/ are referenced by them.
    for (const auto& entry : std::filesystem::directory_iterator("scenes")) {
      if (entry.path().extension() == ".json") scenePaths.push_back(entry.path().string());
    }
    std::sort(scenePaths.begin(), scenePaths.end());
    if (scenePaths.empty()) throw InputError("scenes/: no *.json scene files");
  }
  // The memory a run may take: its pixels and its scene's triangles (MemoryBudget.hpp). Scenes
  // stay loaded between their runs while they fit beside the largest run in half the budget;
  // past that, a scene's geometry is dropped once it is checked and loaded again for its runs.
  const double budget = options.maxMemory.empty()
                            ? availableMemoryBytes()
                            : parseMemorySize(options.maxMemory, "--max-memory");
  const std::string budgetText = options.maxMemory.empty()
                                     ? memoryText(budget) + " is available"
                                     : "--max-memory allows " + memoryText(budget);
  std::vector<Scene> scenes;
  std::vector<bool> loadForItsRuns;  // the geometry was dropped: load it again to run it
  double keptBytes = 0.0;
  for (const std::string& path : scenePaths) {
    currentStep() = "loading " + path;
    scenes.push_back(loadScene(path));
    Scene& scene = scenes.back();
    // What the loaders kept but flagged (degenerate triangles, ...): worth seeing, not fatal.
    for (const std::string& warning : scene.warnings) {
      std::cerr << "clipray: warning: " << warning << "\n";
    }
    const double triangles = static_cast<double>(scene.triangleCount());
    double pixels = 0.0;
    for (const Camera& camera : scene.cameras) {
      const Viewport v = sizeOverride.value_or(camera.viewport);
      pixels = std::max(pixels, static_cast<double>(v.width) * v.height);
    }
    const double runBytes = kRunBytesPerTriangle * triangles + kRunBytesPerPixel * pixels;
    if (budget > 0.0 && runBytes > budget) {
      throw InputError(path + ": one run needs about " + memoryText(runBytes) + " (" +
                       std::to_string(scene.triangleCount()) + " triangles, " +
                       std::to_string(static_cast<long long>(pixels)) + " pixels); " + budgetText);
    }
    const double loadedBytes = kLoadedBytesPerTriangle * triangles;
    const bool keep = budget <= 0.0 || keptBytes + loadedBytes + runBytes <= budget / 2.0;
    loadForItsRuns.push_back(!keep);
    if (keep) {
      keptBytes += loadedBytes;
    } else {
      std::cerr << "clipray: note: " << path << " (" << scene.triangleCount()
                << " triangles) is loaded again for its runs: the scenes do not all stay loaded "
                   "beside a run where "
                << budgetText << "\n";
      scene.objects = {};  // names, cameras and conventions stay for the checks below
    }
  }
  // Runs are filed under their scene's and camera's names: no two may share a folder.
  checkDistinctRunFolders(scenes);

  // 2. The backend, and the limits only it knows.
  std::unique_ptr<gl::GlContext> context = gl::createContext(options.backend);
  gl::Renderer renderer(*context);
  const Viewport maxViewport = renderer.maxViewport();
  auto checkViewport = [&](Viewport v, const std::string& where) {
    const std::string size = std::to_string(v.width) + "x" + std::to_string(v.height);
    if (v.width > maxViewport.width || v.height > maxViewport.height) {
      throw InputError(where + ": " + size + " exceeds GL_MAX_VIEWPORT_DIMS " +
                       std::to_string(maxViewport.width) + "x" +
                       std::to_string(maxViewport.height) + " of " + renderer.info().renderer);
    }
    const double needed = kRunBytesPerPixel * v.width * v.height;
    if (budget > 0.0 && needed > budget) {
      throw InputError(where + ": " + size + " needs about " + memoryText(needed) +
                       " of memory for one run; " + budgetText);
    }
  };
  if (sizeOverride) checkViewport(*sizeOverride, "--size");
  for (const Scene& scene : scenes) {
    for (std::size_t c = 0; c < scene.cameras.size(); ++c) {
      if (!sizeOverride) {
        checkViewport(scene.cameras[c].viewport,
                      scene.path + ": /cameras/" + std::to_string(c) + "/viewport");
      }
    }
  }

  // 3. The runs: scene x camera x convention (one analytic pass) x format x vertex mode.
  //    A progress line on stderr only when a person is watching it.
  //    With --rounds, all of it again, round after round (images in the last round only).
  //    The images --images asks for (and every run's thumbnails, for index.html, unless it says
  //    none) are encoded on worker threads beside the next runs.
  const bool progress = isatty(STDERR_FILENO) != 0;
  std::vector<std::vector<RunRecord>> rounds;
  ImageEncoder encoder;
  for (unsigned round = 1; round <= options.rounds; ++round) {
    const bool lastRound = round == options.rounds;
    std::vector<RunRecord>& runs = rounds.emplace_back();
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      std::optional<Scene> loadedAgain;
      currentStep() = "loading " + scenes[s].path;
      if (loadForItsRuns[s]) loadedAgain.emplace(loadScene(scenes[s].path));
      const Scene& scene = loadedAgain ? *loadedAgain : scenes[s];
      const std::vector<DepthMode> sceneConventions =
          conventions
              ? *conventions
              : (scene.conventions.empty() ? std::vector<DepthMode>{kNegativeOneToOne, kZeroToOne}
                                           : scene.conventions);
      for (const Camera& camera : scene.cameras) {
        if (shard && shardOf(scene.name, camera.name, shard->second) != shard->first) continue;
        const Viewport viewport = sizeOverride.value_or(camera.viewport);
        for (const DepthMode mode : sceneConventions) {
          currentStep() = "tracing " + scene.name + "/" + camera.name + " " + mode.name() + " at " +
                          std::to_string(viewport.width) + "x" + std::to_string(viewport.height);
          const gl::AnalyticPass pass =
              gl::runAnalyticPass(scene, camera, mode, viewport, options.threads);
          for (const DepthFormat format : formats) {
            for (const VertexMode vertexMode : vertexModes) {
              if (progress) {
                std::cerr << "clipray: ";
                if (options.rounds > 1) {
                  std::cerr << "round " << round << "/" << options.rounds << " ";
                }
                std::cerr << scene.name << "/" << camera.name << " " << mode.name() << " "
                          << depthFormatName(format) << " " << vertexModeName(vertexMode)
                          << "\x1b[K\r" << std::flush;
              }
              currentStep() = "running " + scene.name + "/" + camera.name + " " + mode.name() +
                              " " + depthFormatName(format) + " " + vertexModeName(vertexMode);
              gl::ComparedRun compared =
                  gl::rasterAndComparePixels(renderer, pass, format, vertexMode, options.threads);
              if (lastRound && wantsThumbnails(*imagePolicy)) {
                encoder.submit(runs.size(), compared.run, std::move(compared.pixels),
                               wantsImages(*imagePolicy, compared.run.metrics));
              }
              runs.push_back(std::move(compared.run));
            }
          }
        }
      }
    }
  }
  if (progress) std::cerr << "\x1b[K" << std::flush;
  // One record per run, the last round's: the same order as the keys the encoder was given.
  std::vector<RunRecord> runs = mergeRounds(std::move(rounds));
  encoder.collect(runs);

  // 4. Outputs, all at the end and each atomically.
  currentStep() = "writing the report into " + options.out;
  writeReport(options.out, runs, renderer.info(), provenance);
  out.commit();
  if (!options.junit.empty()) writeFileAtomically(options.junit, junitXml(runs, options.out));
  // With --json, stdout carries only the report (parseable); the summary goes to stderr.
  std::ostream& summary = options.json ? std::cerr : std::cout;
  summary << textSummary(runs);
  summary << "report: " << (std::filesystem::path(options.out) / "report.json").string() << "\n";
  if (options.json) {
    std::cout << reportJson(runs, renderer.info(), provenance)
                     .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
              << "\n";
  }
  const bool consistent = std::all_of(runs.begin(), runs.end(),
                                      [](const RunRecord& r) { return r.metrics.consistent(); });
  return consistent ? 0 : 1;
}

int runReconcile(const ReconcileOptions& options) {
  currentStep() = "checking the options";
  try {
    return runReconcileSteps(options);
  } catch (const std::bad_alloc&) {
    throw std::runtime_error("out of memory while " + currentStep() +
                             "; try a smaller --size, fewer scenes, or --max-memory below what "
                             "the machine has");
  }
}

CommandRunner addReconcileOptions(CLI::App& app) {
  auto options = std::make_shared<ReconcileOptions>();
  app.add_option("scenes", options->scenes,
                 "Scene files (.json), or mesh files (.gltf, .glb, .obj, .ply) seen from their "
                 "own cameras, else from automatic ones (default: every scenes/*.json)");
  app.add_option("--backend", options->backend, "GL backend: osmesa, egl")->capture_default_str();
  app.add_option("--conventions", options->conventions,
                 "Comma-separated: no, zo, zo-reversed (default: the scene's list, else no,zo)");
  app.add_option("--depth-formats", options->depthFormats, "Comma-separated: 16, 24, 32f")
      ->capture_default_str();
  app.add_option("--vertex-modes", options->vertexModes,
                 "Comma-separated: world, camera-relative, pretransformed")
      ->capture_default_str();
  app.add_option("--size", options->size, "WxH: override every camera's viewport");
  app.add_option("--out", options->out, "Output folder for report.json and PNGs")
      ->capture_default_str();
  app.add_option("--images", options->images,
                 "Which runs get their four PNGs and cluster crops: failing (the inconsistent "
                 "runs'; every run still gets the thumbnails of index.html), all, none (no "
                 "images at all)")
      ->capture_default_str();
  app.add_option("--junit", options->junit,
                 "Also write the runs as JUnit XML to this file (one test case per run) for CI");
  app.add_flag("--json", options->json, "Also print report.json to stdout");
  app.add_option("--kernels", options->kernels,
                 "Code for the analytic side: simd (AVX2 kernels where the CPU has them), or "
                 "portable (one ray and one pixel at a time in double: the same report and "
                 "images, slower; shows the kernels change nothing)")
      ->capture_default_str();
  app.add_option("--shard", options->shard,
                 "I/N: only shard I of N (1-based) of the scene/camera pairs, split by their "
                 "names, for CI jobs in parallel");
  app.add_option("--max-memory", options->maxMemory,
                 "Memory the runs may use, e.g. 8G or 512M (default: what is available, within "
                 "the cgroup's limit)");
  app.add_option("--threads", options->threads, "Threads for the analytic pass (0: all cores)")
      ->check(CLI::Range(0u, 256u))
      ->capture_default_str();
  app.add_option("--rounds", options->rounds,
                 "Make every run this many times, round after round; timings_ms then holds each "
                 "timing's median over rounds 2.. (the first, cold round is reported apart)")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  return [options] {
    options->provenance = {commandLine(), utcNow()};
    return runReconcile(*options);
  };
}

const bool registered = registerCommand(
    {"reconcile", "Rasterize scenes headlessly and compare every pixel with analytic ray hits", 0,
     addReconcileOptions});

}  // namespace
}  // namespace clipray::cli

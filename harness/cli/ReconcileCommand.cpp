// `clipray reconcile`: rasterize every scene headlessly, trace the same pixels analytically,
// compare. The command line becomes a plan (engine/ReconcilePlan.hpp), the engine runs it, and
// the command prints what it found.

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "Commands.hpp"
#include "clipray/InputError.hpp"
#include "clipray/engine/CaptureReconcile.hpp"
#include "clipray/engine/MemoryBudget.hpp"
#include "clipray/engine/ReconcilePlan.hpp"
#include "clipray/engine/ReconcileRunner.hpp"
#include "clipray/page/PageHtml.hpp"
#include "clipray/page/PageReconcile.hpp"
#include "clipray/report/Report.hpp"
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

// The command line as typed: strings until the plan is made of them.
struct ReconcileArguments {
  std::vector<std::string> scenes;
  std::string backend = "osmesa";
  std::string conventions;  // empty: per scene, default no,zo
  std::string depthFormats = "24,32f";
  std::string vertexModes = "world";
  std::string size;
  std::string out = "report";
  std::string images = "failing";
  std::string kernels = "simd";
  std::string analytic = "auto";
  std::string junit;  // empty: no JUnit file
  bool json = false;
  unsigned threads = 0;
  unsigned rounds = 1;
  int samples = 0;        // 0: each scene's own
  std::string maxMemory;  // empty: what the machine (or the cgroup) has available
  std::string shard;      // "I/N": only the scene/camera pairs of shard I of N
  // --page: a three.js page's own picking against its depth buffer (PageReconcile.hpp).
  std::string page;
  std::string grid = "32x24";
  std::optional<std::uint64_t> frames;
  std::optional<double> timeout;
  bool noToggle = false;
  // --capture: a RenderDoc capture's frame against its camera's rays (CaptureReconcile.hpp).
  std::string capture;
  std::string draws;
};

// "I/N" with 1 <= I <= N <= 100000 (a CI matrix of any size); throws InputError otherwise.
engine::Shard parseShard(const std::string& text) {
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

void checkJUnitPath(const std::string& path) {
  const std::filesystem::path junit(path);
  const std::filesystem::path folder =
      junit.has_parent_path() ? junit.parent_path() : std::filesystem::path(".");
  if (std::filesystem::is_directory(junit)) {
    throw InputError("--junit: " + path + " is a folder; name the XML file to write");
  }
  if (!std::filesystem::is_directory(folder)) {
    throw InputError("--junit: " + path + ": the folder " + folder.string() + " does not exist");
  }
}

// Every scenes/*.json where no scene is named (the mesh files under scenes/assets/ are referenced
// by them).
std::vector<std::string> defaultScenePaths() {
  if (!std::filesystem::is_directory("scenes")) {
    throw InputError(
        "no scene given and there is no scenes/ folder here; name scene files, e.g. clipray "
        "reconcile scenes/standard.json");
  }
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator("scenes")) {
    if (entry.path().extension() == ".json") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  if (paths.empty()) throw InputError("scenes/: no *.json scene files");
  return paths;
}

// Everything the user typed is checked here, before anything is rendered or written.
engine::ReconcilePlan planOf(const ReconcileArguments& arguments) {
  engine::ReconcilePlan plan;
  plan.depthFormats = parseList<DepthFormat>("--depth-formats", arguments.depthFormats,
                                             parseDepthFormat, "16, 24, 32f");
  plan.vertexModes = parseList<VertexMode>("--vertex-modes", arguments.vertexModes, parseVertexMode,
                                           "world, camera-relative, pretransformed");
  const std::optional<ImagePolicy> images = parseImagePolicy(arguments.images);
  if (!images) {
    throw InputError("--images: unknown value \"" + arguments.images +
                     "\"; expected one of: failing, all, none");
  }
  plan.images = *images;
  if (arguments.kernels != "simd" && arguments.kernels != "portable") {
    throw InputError("--kernels: unknown value \"" + arguments.kernels +
                     "\"; expected one of: simd, portable");
  }
  plan.kernels = arguments.kernels == "simd" ? KernelChoice::Simd : KernelChoice::Portable;
  plan.analytic = analyticPathNamed(arguments.analytic);
  if (!plan.analytic) {
    throw InputError("--analytic: unknown value \"" + arguments.analytic +
                     "\"; expected one of: auto, rays, screen");
  }
  if (!arguments.conventions.empty()) {
    plan.conventions =
        parseList<DepthMode>("--conventions", arguments.conventions, DepthMode::parse,
                             "no, zo, zo-reversed (each also with -upper-left)");
  }
  plan.defaultConventions = {kNegativeOneToOne, kZeroToOne};
  plan.provenance = {commandLine(), utcNow()};
  if (!arguments.shard.empty()) {
    plan.shard = parseShard(arguments.shard);
    plan.provenance.shardIndex = plan.shard->index;
    plan.provenance.shardCount = plan.shard->count;
  }
  if (!arguments.size.empty()) plan.size = parseViewportOption(arguments.size, "--size");
  plan.sizeOption = "--size";
  if (!arguments.junit.empty()) checkJUnitPath(arguments.junit);
  plan.junit = arguments.junit;
  plan.out = arguments.out;
  const std::vector<std::string> paths =
      arguments.scenes.empty() ? defaultScenePaths() : arguments.scenes;
  for (const std::string& path : paths) plan.scenes.push_back({path, nullptr});
  if (arguments.maxMemory.empty()) {
    plan.memory = engine::machineMemoryBudget();
  } else {
    const double bytes = engine::parseMemorySize(arguments.maxMemory, "--max-memory");
    plan.memory = {bytes, "--max-memory allows " + engine::memoryText(bytes)};
  }
  plan.backend = arguments.backend;
  plan.threads = arguments.threads;
  plan.rounds = arguments.rounds;
  plan.samples = arguments.samples;
  // A progress line on stderr only when a person is watching it.
  plan.progress = isatty(STDERR_FILENO) != 0;
  return plan;
}

// The summary on stdout (stderr with --json, which prints report.json there instead), and the
// exit status: 0 when every run is consistent.
int printOutcome(const engine::ReconcilePlan& plan, const engine::ReconcileOutcome& outcome,
                 bool json) {
  std::ostream& summary = json ? std::cerr : std::cout;
  summary << textSummary(outcome.runs);
  // Last, the page a person opens (report.json, summary.txt and the images are beside it).
  summary << "report: " << (std::filesystem::path(plan.out) / "index.html").string()
          << " (report.json beside it)\n";
  if (json) {
    std::cout << reportJson(outcome.runs, outcome.gl, plan.provenance)
                     .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
              << "\n";
  }
  return outcome.consistent() ? 0 : 1;
}

// "CxR": the grid of pixel centres --page picks at.
std::pair<int, int> parseGrid(const std::string& text) {
  int columns = 0, rows = 0;
  char x = 0;
  std::istringstream stream(text);
  if (!(stream >> columns >> x >> rows) || (x != 'x' && x != 'X') || !stream.eof() || columns < 1 ||
      rows < 1 || columns > 4096 || rows > 4096) {
    throw InputError("--grid: expected CxR with 1 to 4096 columns and rows (e.g. 32x24), got \"" +
                     text + "\"");
  }
  return {columns, rows};
}

// reconcile --page: the picks' summary on stdout (stderr with --json, which prints the report
// there instead), <out>/page-report.json; 0 consistent, 1 inconsistent. Every option is checked
// before the browser starts, and nothing is written for a page that cannot be reconciled.
int runPageReconcile(const ReconcileArguments& arguments, const CLI::App& app) {
  if (!arguments.scenes.empty()) {
    throw InputError("--page: the page is the scene; give no scene files (got " +
                     arguments.scenes.front() + ")");
  }
  for (const char* option :
       {"--backend", "--conventions", "--depth-formats", "--vertex-modes", "--size", "--images",
        "--junit", "--kernels", "--analytic", "--shard", "--max-memory", "--threads", "--rounds"}) {
    if (app.count(option) > 0) {
      throw InputError(std::string(option) + ": not with --page (the page draws itself)");
    }
  }
  page::PageReconcileOptions options;
  options.page.target = arguments.page;
  std::tie(options.columns, options.rows) = parseGrid(arguments.grid);
  if (arguments.frames) {
    if (*arguments.frames < 1 || *arguments.frames > 100000) {
      throw InputError("--frames: expected a number of frames from 1 to 100000 with --page, got " +
                       std::to_string(*arguments.frames));
    }
    options.page.frames = *arguments.frames;
  }
  if (arguments.timeout) options.page.timeoutSeconds = *arguments.timeout;
  const std::filesystem::path out(arguments.out);
  if (std::filesystem::exists(out) && !std::filesystem::is_directory(out)) {
    throw InputError("--out: " + arguments.out + " is a file, not a folder");
  }
  options.toggle = !arguments.noToggle;
  const page::PageReconcileResult result = page::reconcilePage(options);
  const std::string report =
      page::pageReconcileJson(result).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  std::filesystem::create_directories(out);
  const std::filesystem::path file = out / "page-report.json";
  std::ofstream(file) << report << "\n";
  // index.html beside it, with the picks images it shows (PageHtml.hpp).
  const std::string picks = page::pagePicksPng(result);
  const std::string toggledPicks = result.toggle.run ? page::pagePicksPng(*result.toggle.run) : "";
  const bool images = !picks.empty() && (!result.toggle.run || !toggledPicks.empty());
  // A folder used before keeps no picks image of an earlier run that this index.html does not
  // show.
  std::error_code ignored;
  if (images) {
    std::ofstream(out / "picks.png", std::ios::binary) << picks;
  } else {
    std::filesystem::remove(out / "picks.png", ignored);
  }
  if (images && result.toggle.run) {
    std::ofstream(out / "picks-toggled.png", std::ios::binary) << toggledPicks;
  } else {
    std::filesystem::remove(out / "picks-toggled.png", ignored);
  }
  std::ofstream(out / "index.html") << page::pageReconcileHtml(result, images);
  std::ostream& summary = arguments.json ? std::cerr : std::cout;
  summary << page::pageReconcileText(result) << "report: " << file.string() << " ("
          << (out / "index.html").string() << " beside it)\n";
  if (arguments.json) std::cout << report << "\n";
  return result.allConsistent() ? 0 : 1;
}

// reconcile --capture: the frame's summary on stdout (stderr with --json, which prints
// report.json there instead), the scene report's files under --out; 0 consistent, 1 otherwise.
int runCaptureReconcile(const ReconcileArguments& arguments, const CLI::App& app) {
  if (!arguments.scenes.empty()) {
    throw InputError("--capture: the capture is the scene; give no scene files (got " +
                     arguments.scenes.front() + ")");
  }
  if (!arguments.page.empty()) throw InputError("--capture: not with --page");
  for (const char* option :
       {"--backend", "--conventions", "--depth-formats", "--vertex-modes", "--size", "--images",
        "--junit", "--kernels", "--analytic", "--shard", "--max-memory", "--rounds", "--samples",
        "--grid", "--frames", "--timeout", "--no-toggle"}) {
    if (app.count(option) > 0) {
      throw InputError(std::string(option) + ": not with --capture (the capture holds the frame)");
    }
  }
  const std::filesystem::path out(arguments.out);
  if (std::filesystem::exists(out) && !std::filesystem::is_directory(out)) {
    throw InputError("--out: " + arguments.out + " is a file, not a folder");
  }
  engine::CaptureReconcileOptions options;
  options.capture = arguments.capture;
  options.draws = arguments.draws;
  options.threads = arguments.threads;
  const engine::CaptureReconcileResult result = engine::reconcileCapture(options);
  const std::vector<RunRecord> runs = {result.run};
  const ReportProvenance provenance{commandLine(), utcNow()};
  writeReport(out, runs, engine::captureGlInfo(result), provenance);
  std::ostream& summary = arguments.json ? std::cerr : std::cout;
  summary << textSummary(runs);
  for (const std::string& note : result.run.notes) summary << "note: " << note << "\n";
  summary << "report: " << (out / "index.html").string() << " (report.json beside it)\n";
  if (arguments.json) {
    std::cout << reportJson(runs, engine::captureGlInfo(result), provenance)
                     .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
              << "\n";
  }
  return runVerdict(result.run) == RunVerdict::Consistent ? 0 : 1;
}

CommandRunner addReconcileOptions(CLI::App& app) {
  auto arguments = std::make_shared<ReconcileArguments>();
  app.add_option("scenes", arguments->scenes,
                 "Scene files (.json), or mesh files (.gltf, .glb, .obj, .ply) seen from their "
                 "own cameras, else from automatic ones (default: every scenes/*.json)");
  app.add_option("--backend", arguments->backend, "GL backend: osmesa, egl")->capture_default_str();
  app.add_option("--conventions", arguments->conventions,
                 "Comma-separated: no, zo, zo-reversed, each also with -upper-left for "
                 "glClipControl(GL_UPPER_LEFT, ...) (default: the scene's list, else no,zo)");
  app.add_option("--depth-formats", arguments->depthFormats, "Comma-separated: 16, 24, 32f")
      ->capture_default_str();
  app.add_option("--vertex-modes", arguments->vertexModes,
                 "Comma-separated: world, camera-relative, pretransformed")
      ->capture_default_str();
  app.add_option("--size", arguments->size, "WxH: override every camera's viewport");
  app.add_option("--out", arguments->out, "Output folder for report.json and PNGs")
      ->capture_default_str();
  app.add_option("--images", arguments->images,
                 "Which runs get their four PNGs and cluster crops: failing (the inconsistent "
                 "runs'; every run still gets the thumbnails of index.html), all, none (no "
                 "images at all)")
      ->capture_default_str();
  app.add_option("--junit", arguments->junit,
                 "Also write the runs as JUnit XML to this file (one test case per run) for CI");
  app.add_flag("--json", arguments->json, "Also print report.json to stdout");
  app.add_option("--kernels", arguments->kernels,
                 "Code for the analytic side: simd (AVX2 kernels where the CPU has them), or "
                 "portable (one ray and one pixel at a time in double: the same report and "
                 "images, slower; shows the kernels change nothing)")
      ->capture_default_str();
  app.add_option("--analytic", arguments->analytic,
                 "How clipray's own rays find their hits: screen (each triangle's coverage and "
                 "depth decided at the pixel centres, with bounds that make every decision the "
                 "ray path's, the pixels they cannot decide traced, depths compared from the "
                 "triangles' planes), rays (each pixel's robust ray traced, depths compared at "
                 "its hit), or auto (screen where a frame has 16 pixels or more a triangle): the "
                 "same classes and counts, figures within a hair")
      ->capture_default_str();
  app.add_option("--shard", arguments->shard,
                 "I/N: only shard I of N (1-based) of the scene/camera pairs, split by their "
                 "names, for CI jobs in parallel");
  app.add_option("--max-memory", arguments->maxMemory,
                 "Memory the runs may use, e.g. 8G or 512M (default: what is available, within "
                 "the cgroup's limit)");
  app.add_option("--threads", arguments->threads, "Threads for the analytic pass (0: all cores)")
      ->check(CLI::Range(0u, 256u))
      ->capture_default_str();
  app.add_option("--samples", arguments->samples,
                 "Samples per pixel: above 1 the frame is drawn multisampled and every sample is "
                 "compared with rays through its own position (a count the GL implementation "
                 "offers; llvmpipe: 4); default: each scene's \"samples\", else 1")
      ->check(CLI::Range(1, 64));
  app.add_option("--rounds", arguments->rounds,
                 "Make every run this many times, round after round; timings_ms then holds each "
                 "timing's median over rounds 2.. (the first, cold round is reported apart)")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  app.add_option("--page", arguments->page,
                 "A three.js page (http(s) or file URL, or an HTML file): call its own "
                 "Raycaster.setFromCamera at a grid of pixel centres in headless chromium and "
                 "compare each first hit's depth with the page's depth buffer");
  app.add_option("--grid", arguments->grid, "With --page: CxR pixel centres to pick at")
      ->capture_default_str();
  app.add_option("--frames", arguments->frames,
                 "With --page: animation frames to let the page draw first (default 3)");
  app.add_option("--timeout", arguments->timeout,
                 "With --page: seconds to wait for the page's frames (default 30)");
  app.add_flag("--no-toggle", arguments->noToggle,
               "With --page: only the page as it is, not also a second load with its "
               "reversedDepthBuffer toggled (which costs about one more page load and its picks)");
  app.add_option("--capture", arguments->capture,
                 "A RenderDoc capture (.rdc) of an OpenGL app: its frame's depth buffer against "
                 "the picking rays of the camera matrix in its uniforms, through the draws' own "
                 "vertex shader output");
  app.add_option("--draws", arguments->draws,
                 "With --capture: only the draws with RenderDoc event IDs A-B (or A)");
  return [arguments, &app] {
    if (!arguments->capture.empty()) return runCaptureReconcile(*arguments, app);
    if (!arguments->draws.empty()) throw InputError("--draws needs --capture");
    if (!arguments->page.empty()) return runPageReconcile(*arguments, app);
    if (app.count("--grid") > 0 || arguments->frames || arguments->timeout) {
      throw InputError("--grid, --frames and --timeout need --page");
    }
    if (arguments->noToggle) throw InputError("--no-toggle needs --page");
    const engine::ReconcilePlan plan = planOf(*arguments);
    return printOutcome(plan, engine::runReconcilePlan(plan), arguments->json);
  };
}

const bool registered = registerCommand(
    {"reconcile", "Rasterize scenes headlessly and compare every pixel with analytic ray hits", 0,
     addReconcileOptions});

}  // namespace
}  // namespace clipray::cli

// `clipray bench`: every ray method x precision on the hard cases (or on a user's own matrix):
// speed per ray and error against the __float128 reference, as a table, JSON rows and an SVG.

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "Commands.hpp"
#include "clipray/InputError.hpp"
#include "clipray/rays/HardCases.hpp"
#include "clipray/rays/QuadReference.hpp"
#include "clipray/rays/RayErrors.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/report/SvgPlot.hpp"
#include "clipray/util/OptionValues.hpp"

namespace clipray::cli {

namespace {

// The default grid finishes every case in well under a minute; --full measures at 1920x1080
// (about 9 times the pixels, minutes).
constexpr const char* kQuickSize = "640x360";
constexpr const char* kFullSize = "1920x1080";

struct BenchOptions {
  std::string cases;
  std::string methods;
  std::string size;  // empty: kQuickSize, or kFullSize with --full
  bool full = false;
  std::string clipFromWorld;
  std::string layout = "column-major";
  std::string convention;
  std::string json;
  std::string plot;
};

struct Row {
  std::string caseName, convention, method, precision;
  double nsPerRay = 0.0;
  MethodErrors errors;
  double floorAnglePx = 0.0;        // what the matrix stored in float costs
  double outputFloorAnglePx = 0.0;  // what storing the exact ray in this precision costs
  double floorOriginPx = 0.0;       // the same two for the origin (lateral, near-plane pixels)
  double outputFloorOriginPx = 0.0;
  std::optional<double> fovYDegrees;
  bool parallel = false;
};

template <typename T>
double timeGenerator(const RayGenerator<T>& generator, double budgetSeconds) {
  // Row by row into one cache-resident row buffer, as a tracer consuming the rays would.
  const Viewport v = generator.viewport();
  RayBuffer<T> buffer(static_cast<std::size_t>(v.width));
  const RaySpan<T> span = buffer.span(0, v.width);
  using Clock = std::chrono::steady_clock;
  double best = std::numeric_limits<double>::infinity();
  double spent = 0.0;
  for (int repeat = 0; repeat < 50 && (repeat < 3 || spent < budgetSeconds); ++repeat) {
    const auto start = Clock::now();
    for (int j = 0; j < v.height; ++j) generator.generateRow(j, span);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    spent += seconds;
    best = std::min(best, seconds);
    if (seconds > 1.0) break;  // slow methods: one pass is plenty
  }
  volatile float sink = static_cast<float>(span.directionX[0]);
  (void)sink;
  return best * 1e9 / (static_cast<double>(v.width) * v.height);
}

struct CaseJob {
  HardCase hardCase;
  // The convention the rows name: the case's own, or the user's --convention as given, its clip
  // origin included (which changes no figure: the matrix is measured as given).
  std::string convention;
  std::vector<RayMethod> methods;
  // Seconds of repeated passes per method and precision (best pass kept): the quick default's
  // 36 cases x 16 timings would spend most of their minute here at the full sweep's budget.
  double timingBudgetSeconds = 0.15;
};

// Measures one case: timings (single thread, nothing else running), then errors on all cores.
std::vector<Row> measureCase(const CaseJob& job, bool progress, const std::string& progressTag) {
  const HardCase& c = job.hardCase;
  const Viewport v = c.viewport;
  std::vector<std::unique_ptr<RayGenerator<float>>> floats;
  std::vector<std::unique_ptr<RayGenerator<double>>> doubles;
  std::vector<Row> rows;
  const bool parallel = describeProjection(c.inputs.clipFromWorld, c.inputs.mode)
                            .facts.value_or(ProjectionFacts{})
                            .parallel;
  for (const RayMethod method : job.methods) {
    auto f = makeRayGenerator<float>(method, c.inputs, v);
    auto d = makeRayGenerator<double>(method, c.inputs, v);
    if (!f || !d) continue;
    for (const Precision precision : kPrecisions) {
      Row row;
      row.caseName = c.name;
      row.convention = job.convention;
      row.method = rayMethodName(method);
      row.precision = precisionName(precision);
      row.fovYDegrees = c.fovYDegrees;
      row.parallel = parallel;
      row.nsPerRay = precision == Precision::Float ? timeGenerator(*f, job.timingBudgetSeconds)
                                                   : timeGenerator(*d, job.timingBudgetSeconds);
      rows.push_back(row);
    }
    floats.push_back(std::move(f));
    doubles.push_back(std::move(d));
  }
  if (progress) {
    std::cerr << "clipray bench: " << progressTag << " " << c.name << " " << job.convention
              << ": reference (__float128)...\x1b[K\r" << std::flush;
  }

  // References: the exact rays of the float-rounded entries (judge float methods), of the double
  // entries (judge double methods); their difference is the float floor.
  const glm::dmat4 floatEntries = glm::dmat4(glm::mat4(c.inputs.clipFromWorld));
  const QuadReference floatReference(floatEntries, c.inputs.mode, v);
  const QuadReference doubleReference(c.inputs.clipFromWorld, c.inputs.mode, v);

  const unsigned threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  struct Partial {
    std::vector<ErrorAccumulator> floatErrors, doubleErrors;
    double floorMax = 0.0;
    double outputFloorFloat = 0.0, outputFloorDouble = 0.0;
    double originFloorMax = 0.0;
    double outputOriginFloorFloat = 0.0, outputOriginFloorDouble = 0.0;
  };
  std::vector<Partial> partials(threads);
  auto work = [&](unsigned t) {
    Partial& partial = partials[t];
    for (std::size_t m = 0; m < floats.size(); ++m) {
      const bool tMax = methodProvidesTMax(*parseRayMethod(rows[2 * m].method));
      partial.floatErrors.emplace_back(tMax);
      partial.doubleErrors.emplace_back(tMax);
    }
    std::vector<ReferenceRay> floatRow, doubleRow;
    RayBuffer<float> floatRays(static_cast<std::size_t>(v.width));
    RayBuffer<double> doubleRays(static_cast<std::size_t>(v.width));
    for (int j = static_cast<int>(t); j < v.height; j += static_cast<int>(threads)) {
      floatReference.row(j, floatRow);
      doubleReference.row(j, doubleRow);
      partial.floorMax = std::max(partial.floorMax, floorAngleRowMax(floatRow, doubleRow));
      partial.outputFloorFloat =
          std::max(partial.outputFloorFloat, outputFloorAngleRowMax<float>(floatRow));
      partial.outputFloorDouble =
          std::max(partial.outputFloorDouble, outputFloorAngleRowMax<double>(doubleRow));
      partial.originFloorMax =
          std::max(partial.originFloorMax, floorOriginRowMax(floatRow, doubleRow));
      partial.outputOriginFloorFloat =
          std::max(partial.outputOriginFloorFloat, outputFloorOriginRowMax<float>(floatRow));
      partial.outputOriginFloorDouble =
          std::max(partial.outputOriginFloorDouble, outputFloorOriginRowMax<double>(doubleRow));
      for (std::size_t m = 0; m < floats.size(); ++m) {
        floats[m]->generateRow(j, floatRays.span(0, v.width));
        partial.floatErrors[m].addRow(floatRow, floatRays.span(0, v.width));
        doubles[m]->generateRow(j, doubleRays.span(0, v.width));
        partial.doubleErrors[m].addRow(doubleRow, doubleRays.span(0, v.width));
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& thread : pool) thread.join();
  double floorMax = 0.0, outputFloorFloat = 0.0, outputFloorDouble = 0.0;
  double originFloorMax = 0.0, outputOriginFloorFloat = 0.0, outputOriginFloorDouble = 0.0;
  for (const Partial& p : partials) {
    floorMax = std::max(floorMax, p.floorMax);
    outputFloorFloat = std::max(outputFloorFloat, p.outputFloorFloat);
    outputFloorDouble = std::max(outputFloorDouble, p.outputFloorDouble);
    originFloorMax = std::max(originFloorMax, p.originFloorMax);
    outputOriginFloorFloat = std::max(outputOriginFloorFloat, p.outputOriginFloorFloat);
    outputOriginFloorDouble = std::max(outputOriginFloorDouble, p.outputOriginFloorDouble);
  }
  for (std::size_t m = 0; m < floats.size(); ++m) {
    ErrorAccumulator f = partials[0].floatErrors[m], d = partials[0].doubleErrors[m];
    for (unsigned t = 1; t < threads; ++t) {
      f.merge(partials[t].floatErrors[m]);
      d.merge(partials[t].doubleErrors[m]);
    }
    rows[2 * m].errors = f.result();
    rows[2 * m].floorAnglePx = floorMax;
    rows[2 * m].outputFloorAnglePx = outputFloorFloat;
    rows[2 * m + 1].outputFloorAnglePx = outputFloorDouble;
    rows[2 * m + 1].errors = d.result();
    rows[2 * m + 1].floorAnglePx = 0.0;  // the double entries are the camera: nothing is lost
    rows[2 * m].floorOriginPx = originFloorMax;
    rows[2 * m].outputFloorOriginPx = outputOriginFloorFloat;
    rows[2 * m + 1].floorOriginPx = 0.0;
    rows[2 * m + 1].outputFloorOriginPx = outputOriginFloorDouble;
  }
  return rows;
}

nlohmann::json number(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

std::string cpuName() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown CPU";
}

std::string cell(double value) {
  if (std::isnan(value)) return "-";
  if (std::isinf(value)) return "inf";
  std::ostringstream out;
  out << std::setprecision(2) << std::scientific << value;
  return out.str();
}

std::string table(const std::vector<Row>& rows) {
  // The convention column fits the hard cases' names ("zo-reversed"), and widens for a user's
  // matrix drawn under an upper-left origin ("zo-reversed-upper-left").
  std::size_t conventionWidth = 12;
  for (const Row& r : rows) conventionWidth = std::max(conventionWidth, r.convention.size() + 1);
  const int conv = static_cast<int>(conventionWidth);
  std::ostringstream out;
  out << std::left << std::setw(22) << "case" << std::setw(conv) << "conv" << std::setw(16)
      << "method" << std::setw(7) << "prec" << std::right << std::setw(9) << "ns/ray"
      << std::setw(10) << "ang max" << std::setw(10) << "ang p50" << std::setw(10) << "org max"
      << std::setw(10) << "org p50" << std::setw(10) << "tmax rel" << std::setw(9) << "nonfin"
      << std::setw(9) << "backw" << std::setw(10) << "floor" << std::setw(10) << "out floor"
      << std::setw(10) << "org floor" << std::setw(10) << "org out" << std::setw(9) << "no ray"
      << "\n";
  for (const Row& r : rows) {
    std::ostringstream ns;
    ns << std::fixed << std::setprecision(r.nsPerRay < 10 ? 2 : 1) << r.nsPerRay;
    out << std::left << std::setw(22) << r.caseName << std::setw(conv) << r.convention
        << std::setw(16) << r.method << std::setw(7) << r.precision << std::right << std::setw(9)
        << ns.str() << std::setw(10) << cell(r.errors.anglePx.max) << std::setw(10)
        << cell(r.errors.anglePx.p50) << std::setw(10) << cell(r.errors.originLateralPx.max)
        << std::setw(10) << cell(r.errors.originLateralPx.p50) << std::setw(10)
        << cell(r.errors.tMaxRelativeMax) << std::setw(9) << r.errors.nonfinite << std::setw(9)
        << r.errors.backward << std::setw(10) << cell(r.floorAnglePx) << std::setw(10)
        << cell(r.outputFloorAnglePx) << std::setw(10) << cell(r.floorOriginPx) << std::setw(10)
        << cell(r.outputFloorOriginPx) << std::setw(9) << r.errors.noRay << "\n";
  }
  return out.str();
}

std::string plotSvg(const std::vector<Row>& rows, Viewport size) {
  // The overview: one point per method x precision, the median ns/ray over the cases against the
  // worst angle over the cases. Below it, one panel per case with that case's own figures.
  struct Summary {
    int key = 0;
    std::size_t series = 0;
    std::vector<double> ns;
    double worst = 0.0;      // as plotted: clamped to 1e-12 px, the log axis' floor
    double trueWorst = 0.0;  // as measured, for the key
    bool nonfinite = false;
  };
  const auto angleOf = [](const Row& r) {
    const bool nonfinite = r.errors.nonfinite > 0 || !std::isfinite(r.errors.anglePx.max);
    return nonfinite ? std::numeric_limits<double>::infinity()
                     : std::max(r.errors.anglePx.max, 1e-12);
  };
  std::map<std::string, Summary> byName;
  std::vector<std::string> order;
  std::map<std::string, LogLogPanel> byCase;
  std::vector<std::string> caseOrder;
  for (const Row& r : rows) {
    const std::string name = r.method + " " + r.precision;
    if (!byName.count(name)) {
      order.push_back(name);
      byName[name].key = static_cast<int>(order.size());
      byName[name].series = r.precision == "double" ? 1 : 0;
    }
    Summary& s = byName[name];
    s.ns.push_back(r.nsPerRay);
    const double angle = angleOf(r);
    if (std::isinf(angle)) s.nonfinite = true;
    if (std::isfinite(angle)) {
      s.worst = std::max(s.worst, angle);
      s.trueWorst = std::max(s.trueWorst, r.errors.anglePx.max);
    }
    const std::string caseName = r.caseName + " (" + r.convention + ")";
    if (!byCase.count(caseName)) {
      caseOrder.push_back(caseName);
      byCase[caseName].title = caseName;
    }
    byCase[caseName].points.push_back({s.key, r.nsPerRay, angle, s.series});
  }
  SpeedErrorFigure figure;
  figure.title = "clipray bench: speed vs worst angular error (" + std::to_string(size.width) +
                 "x" + std::to_string(size.height) + ", " + batchCodePath() + ")";
  figure.xLabel = "ns per ray (one core)";
  figure.yLabel = "worst angular error (pixels)";
  figure.series = {{"float", "#1f77b4", MarkerShape::Circle},
                   {"double", "#d62728", MarkerShape::Square}};
  figure.yLines = {{1.0, "1 px"}, {0.01, "0.01 px"}};
  figure.overview.title = "All cases: median ns per ray, worst error over the cases";
  figure.keyTitle = "Key: method precision, median ns/ray, worst px (measured)";
  for (const std::string& name : order) {
    Summary& s = byName[name];
    std::sort(s.ns.begin(), s.ns.end());
    const double median = s.ns[s.ns.size() / 2];
    const double worst = s.nonfinite ? std::numeric_limits<double>::infinity() : s.worst;
    figure.overview.points.push_back({s.key, median, worst, s.series});
    std::ostringstream text;
    text << std::left << std::setw(22) << name << std::right << std::setw(9) << std::setprecision(3)
         << median << " ns " << std::setw(9)
         << (s.nonfinite ? std::string("non-finite rays") : cell(s.trueWorst) + " px");
    figure.key.push_back({s.key, s.series, text.str()});
  }
  for (const std::string& caseName : caseOrder) figure.perCase.push_back(byCase[caseName]);
  return renderSvg(figure);
}

int runBench(const BenchOptions& options) {
  // 1. Everything the user handed us is checked before anything runs.
  // Each case's errors are measured against a __float128 reference at every pixel: 8K (about
  // 33 Mpx) already takes minutes per case on one core; beyond it only the wait grows.
  constexpr int kMaxBenchDimension = 7680;
  if (options.full && !options.size.empty()) {
    throw InputError("--full and --size exclude each other (--full is --size " +
                     std::string(kFullSize) + ")");
  }
  const Viewport size = parseViewportOption(
      options.size.empty() ? (options.full ? kFullSize : kQuickSize) : options.size, "--size",
      kMaxBenchDimension);
  std::vector<std::string> methodNames;
  for (const RayMethod m : kRayMethods) methodNames.push_back(rayMethodName(m));
  std::vector<RayMethod> methods;
  for (const std::string& name :
       splitCommaList(options.methods.empty() ? joinNames(methodNames) : options.methods)) {
    const std::optional<RayMethod> method = parseRayMethod(name);
    if (!method) {
      throw InputError("--methods: unknown method \"" + name +
                       "\"; valid methods: " + joinNames(methodNames));
    }
    if (std::find(methods.begin(), methods.end(), *method) == methods.end()) {
      methods.push_back(*method);
    }
  }
  if (methods.empty()) throw InputError("--methods: expected one of: " + joinNames(methodNames));
  if (options.layout != "column-major" && options.layout != "row-major") {
    throw InputError("--layout: expected column-major or row-major, got \"" + options.layout +
                     "\"");
  }

  std::vector<HardCase> cases;
  std::string userConvention;  // --convention as given, its clip origin included
  if (!options.clipFromWorld.empty()) {
    if (!options.cases.empty()) {
      throw InputError("--cases and --clip-from-world exclude each other");
    }
    if (options.convention.empty()) {
      throw InputError(
          "--clip-from-world needs --convention no|zo|zo-reversed, each also with -upper-left "
          "(the conventions it is drawn under)");
    }
    const std::optional<DepthMode> mode = DepthMode::parse(options.convention);
    if (!mode) {
      throw InputError(
          "--convention: expected no, zo or zo-reversed (each also with -upper-left), got \"" +
          options.convention + "\"");
    }
    userConvention = mode->name();
    HardCase user;
    user.name = "user";
    user.description = "--clip-from-world";
    user.viewport = size;
    // The matrix is measured as given, whatever the origin: under GL_UPPER_LEFT the app computes
    // y' = (2r + 1) / H - 1 from the mouse row r counted from the top, the bench's own formula
    // for row r, so it computes the bench's rays, each for the mirrored framebuffer row, and every
    // figure is over all pixels (docs/bench.md, "Clip origin"). The rows keep the name as given.
    user.inputs.clipFromWorld = parseMatrixOption(
        options.clipFromWorld, options.layout == "row-major", "--clip-from-world");
    user.inputs.mode = mode->lowerLeft();
    const ProjectionCheck check = describeProjection(user.inputs.clipFromWorld, user.inputs.mode);
    if (!check.facts) throw InputError("--clip-from-world: " + check.problem);
    if (!check.facts->parallel) user.fovYDegrees = check.facts->fovYDegrees;
    cases.push_back(user);
  } else {
    if (!options.convention.empty()) {
      throw InputError("--convention applies to --clip-from-world only");
    }
    const std::vector<HardCase> all = hardCases(size);
    const std::vector<std::string> names = hardCaseNames();
    if (options.cases.empty()) {
      cases = all;
    } else {
      for (const std::string& name : splitCommaList(options.cases)) {
        if (std::find(names.begin(), names.end(), name) == names.end()) {
          throw InputError("--cases: unknown case \"" + name +
                           "\"; valid cases: " + joinNames(names));
        }
      }
      const std::vector<std::string> wanted = splitCommaList(options.cases);
      for (const HardCase& c : all) {
        if (std::find(wanted.begin(), wanted.end(), c.name) != wanted.end()) cases.push_back(c);
      }
    }
  }

  auto conventionOf = [&](const HardCase& c) {
    return userConvention.empty() ? c.convention() : userConvention;
  };

  // Output files: their folders must exist before minutes of measuring are spent.
  for (const auto& [option, path] : {std::pair<std::string, std::string>{"--json", options.json},
                                     std::pair<std::string, std::string>{"--plot", options.plot}}) {
    if (path.empty()) continue;
    const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
    if (!std::filesystem::is_directory(parent)) {
      throw InputError(option + ": folder " + parent.string() + " does not exist");
    }
    if (std::filesystem::is_directory(path))
      throw InputError(option + ": " + path + " is a folder");
  }
  // 2. The measurements: a progress line on stderr while the reference runs (when a person
  //    watches stderr), else one line per case as it starts (a log or a pipe).
  const bool progress = isatty(STDERR_FILENO) != 0;
  std::vector<Row> rows;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string tag = "[" + std::to_string(k + 1) + "/" + std::to_string(cases.size()) + "]";
    if (!progress) {
      std::cerr << "clipray bench: " << tag << " " << cases[k].name << " " << conventionOf(cases[k])
                << " (" << size.width << "x" << size.height << ")\n"
                << std::flush;
    }
    const bool quick = !options.full && options.size.empty();
    std::vector<Row> caseRows = measureCase(
        {cases[k], conventionOf(cases[k]), methods, quick ? 0.02 : 0.15}, progress, tag);
    rows.insert(rows.end(), caseRows.begin(), caseRows.end());
  }
  if (progress) std::cerr << "\x1b[K" << std::flush;

  // 3. Outputs.
  std::cout << "clipray bench: " << cpuName() << ", batch code path " << batchCodePath()
            << ", one core for timings\n";
  std::cout << "size " << size.width << "x" << size.height
            << (options.full || !options.size.empty() ? ""
                                                      : " (the quick default; --full: 1920x1080)")
            << "\n";
  std::cout << "errors in pixels (angle: pixel angles; org: lateral origin error in near-plane "
               "pixel footprints); floor: what the float matrix costs; out floor: what storing the "
               "exact ray's direction in the row's precision costs; org floor, org out: the same "
               "two for the origin; no ray: pixels whose line of "
               "sight never crosses the near plane in front of the eye (an oblique near plane's "
               "horizon in view), measured no further\n";
  std::cout << table(rows);
  if (!options.json.empty()) {
    nlohmann::json json;
    json["tool"] = "clipray";
    json["machine"] = {{"cpu", cpuName()}, {"batch_code_path", batchCodePath()}};
    json["size"] = {{"width", size.width}, {"height", size.height}};
    json["rows"] = nlohmann::json::array();
    for (const Row& r : rows) {
      json["rows"].push_back({
          {"case", r.caseName},
          {"convention", r.convention},
          {"method", r.method},
          {"precision", r.precision},
          {"ns_per_ray", number(r.nsPerRay)},
          {"angle_err_px",
           {{"max", number(r.errors.anglePx.max)}, {"p50", number(r.errors.anglePx.p50)}}},
          {"origin_lateral_err_px",
           {{"max", number(r.errors.originLateralPx.max)},
            {"p50", number(r.errors.originLateralPx.p50)}}},
          {"tmax_rel_err", {{"max", number(r.errors.tMaxRelativeMax)}}},
          {"nonfinite", r.errors.nonfinite},
          {"backward", r.errors.backward},
          {"floor_angle_px", number(r.floorAnglePx)},
          {"floor_output_angle_px", number(r.outputFloorAnglePx)},
          {"floor_origin_px", number(r.floorOriginPx)},
          {"floor_output_origin_px", number(r.outputFloorOriginPx)},
          {"no_ray", r.errors.noRay},
          {"no_ray_disagree", r.errors.noRayDisagree},
      });
    }
    writeFileAtomically(options.json, json.dump(2) + "\n");
    std::cout << "json: " << options.json << "\n";
  }
  if (!options.plot.empty()) {
    writeFileAtomically(options.plot, plotSvg(rows, size));
    std::cout << "plot: " << options.plot << "\n";
  }
  return 0;
}

CommandRunner addBenchOptions(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  std::string caseList = joinNames(hardCaseNames());
  app.add_option("--cases", options->cases,
                 "Comma-separated hard cases (default: all): " + caseList);
  app.add_option("--methods", options->methods,
                 "Comma-separated methods (default: all): unproject_glm, two_point, inverse_pv, "
                 "fov_tangent, plane_cross, plane_cross_pre, full, robust");
  app.add_option("--size", options->size,
                 "WxH of the pixel grid (default: " + std::string(kQuickSize) + ")");
  app.add_flag("--full", options->full,
               "The full sweep at " + std::string(kFullSize) + " (minutes; same as --size " +
                   kFullSize + ")");
  app.add_option("--clip-from-world", options->clipFromWorld,
                 "Bench your own matrix: \"16 numbers\" (with --convention)");
  app.add_option("--layout", options->layout, "Order of the 16 numbers: column-major, row-major")
      ->capture_default_str();
  app.add_option("--convention", options->convention,
                 "Convention the matrix is drawn under: no, zo, zo-reversed, each also with "
                 "-upper-left (glClipControl(GL_UPPER_LEFT, ...))");
  app.add_option("--json", options->json, "Write the rows as JSON to FILE");
  app.add_option("--plot", options->plot, "Write speed vs worst error as an SVG to FILE.svg");
  return [options] { return runBench(*options); };
}

const bool registered = registerCommand(
    {"bench",
     "Time every ray method and measure its error against a __float128 reference on hard cases", 20,
     addBenchOptions});

}  // namespace
}  // namespace clipray::cli

// report.json, the text summary and the merging of rounds (ReportFiles.cpp writes them to disk).

#include "clipray/report/Report.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>

#include "clipray/InputError.hpp"
#include "clipray/util/Check.hpp"
#include "clipray/util/OptionValues.hpp"
#include "clipray/util/Version.hpp"

namespace clipray {
namespace {

// JSON number, or null for NaN and infinities (JSON has no spelling for them).
nlohmann::json number(double value) {
  if (!std::isfinite(value)) return nullptr;
  return value;
}

nlohmann::json distribution(const Distribution& d, bool withP50) {
  nlohmann::json out = {{"max", number(d.max)}, {"p99", number(d.p99)}};
  if (withP50) out["p50"] = number(d.p50);
  return out;
}

constexpr std::array<const char*, 4> kImageNames{"raster_depth", "ray_depth", "error_heatmap",
                                                 "mismatch"};

// The path of the run's image named `file` ("mismatch.png"), or null when it has none.
nlohmann::json imagePath(const RunRecord& run, const std::string& file) {
  for (const EncodedImage& image : run.images) {
    const std::string& path = image.relativePath;
    if (path == file || (path.size() > file.size() && path.ends_with(file) &&
                         path[path.size() - file.size() - 1] == '/')) {
      return path;
    }
  }
  return nullptr;
}

nlohmann::json imagesJson(const RunRecord& run) {
  nlohmann::json out = nlohmann::json::object();
  for (const char* name : kImageNames) out[name] = imagePath(run, std::string(name) + ".png");
  return out;
}

nlohmann::json thumbnailsJson(const RunRecord& run) {
  return {{"mismatch", imagePath(run, "thumb_mismatch.png")},
          {"heatmap", imagePath(run, "thumb_heatmap.png")}};
}

// A box in GL window coordinates (y up from the bottom row), or in image coordinates (y down from
// the top row) for a frame `height` rows high.
nlohmann::json boundsJson(const MismatchCluster& c, int height, bool image) {
  return {{"x_min", c.minX},
          {"y_min", image ? imageY(c.maxY, height) : c.minY},
          {"x_max", c.maxX},
          {"y_max", image ? imageY(c.minY, height) : c.maxY}};
}

// What one side hit: null for nothing.
nlohmann::json hitJson(const SurfaceHit& hit) {
  if (!hit.hit()) return nullptr;
  return {{"id", hit.id},
          {"object", hit.object},
          {"kind", hit.kind},
          {"triangle", hit.triangle >= 0 ? nlohmann::json(hit.triangle) : nlohmann::json(nullptr)},
          {"depth", number(hit.depth)}};
}

// The pixel's class, what each side hit there and the error / tolerance, into `out`.
void addHitsJson(nlohmann::json& out, const PixelHits& hits) {
  out["class"] = pixelClassName(hits.pixelClass);
  out["raster"] = hitJson(hits.raster);
  out["ray"] = hitJson(hits.ray);
  out["tolerance_ratio"] = number(hits.toleranceRatio);
}

nlohmann::json worstPixelJson(const RunRecord& run) {
  if (!run.worstPixel) return nullptr;
  const PixelHits& hits = *run.worstPixel;
  nlohmann::json out = {{"pixel_gl", {{"x", hits.x}, {"y", hits.y}}},
                        {"pixel_image", {{"x", hits.x}, {"y", imageY(hits.y, run.size.height)}}}};
  addHitsJson(out, hits);
  return out;
}

nlohmann::json clustersJson(const RunRecord& run) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < run.clusters.largest.size(); ++k) {
    const MismatchCluster& c = run.clusters.largest[k];
    const int height = run.size.height;
    list.push_back({
        {"pixels", c.pixels},
        {"coverage_unexplained", c.coverageUnexplained},
        {"id_unexplained", c.idUnexplained},
        {"depth_beyond_tolerance", c.depthBeyondTolerance},
        {"pixel_gl", {{"x", c.x}, {"y", c.y}}},
        {"pixel_image", {{"x", c.x}, {"y", imageY(c.y, height)}}},
        {"bounds_gl", boundsJson(c, height, false)},
        {"bounds_image", boundsJson(c, height, true)},
        {"crop", imagePath(run, "cluster" + std::to_string(k + 1) + ".png")},
    });
    if (k < run.clusterHits.size()) addHitsJson(list.back(), run.clusterHits[k]);
  }
  return list;
}

// Depth figures per surface kind ("triangle", "sphere", ...): the GLSL float rays of the
// analytic primitives against the CPU's double rays, apart from the triangles.
nlohmann::json byKindJson(const RunMetrics& m) {
  nlohmann::json kinds = nlohmann::json::object();
  for (const RunMetrics::KindFigures& figures : m.byKind) {
    kinds[figures.kind] = {
        {"depth_compared", figures.depthCompared},
        {"depth_error_quanta", distribution(figures.depthErrorQuanta, true)},
        {"distance_rel_error", distribution(figures.distanceRelError, true)},
        {"tolerance_ratio", distribution(figures.toleranceRatio, false)},
    };
  }
  return kinds;
}

nlohmann::json timingsJson(const RunTimings& t) {
  return {{"raster", number(t.raster)},
          {"readback", number(t.readback)},
          {"rays", number(t.rays)},
          {"intersect", number(t.intersect)},
          {"compare", number(t.compare)}};
}

// The convention check's findings on the run's camera (RunFinding): always an array, empty
// without findings, so a reader tells "checked, nothing found" from an older report.
nlohmann::json conventionCheckJson(const RunRecord& run) {
  nlohmann::json list = nlohmann::json::array();
  for (const RunFinding& f : run.conventionFindings) {
    list.push_back({{"severity", f.severity},
                    {"code", f.code},
                    {"message", f.message},
                    {"fix", f.fix},
                    {"expected", f.expected}});
  }
  return list;
}

nlohmann::json runJson(const RunRecord& run) {
  const RunMetrics& m = run.metrics;
  nlohmann::json json = {
      {"scene", run.scene},
      {"camera", run.camera},
      {"convention", run.convention.name()},
      {"depth_format", depthFormatName(run.depthFormat)},
      {"vertex_mode", vertexModeName(run.vertexMode)},
      {"size", {{"width", run.size.width}, {"height", run.size.height}}},
      {"pixels", m.pixels},
      {"raster_hits", m.rasterHits},
      {"ray_hits", m.rayHits},
      {"coverage_mismatch",
       {{"total", m.coverageMismatch.total},
        {"edge_ambiguous", m.coverageMismatch.edgeAmbiguous},
        {"unexplained", m.coverageMismatch.unexplained}}},
      {"id_mismatch",
       {{"total", m.idMismatch.total},
        {"depth_ambiguous", m.idMismatch.depthAmbiguous},
        {"edge_ambiguous", m.idMismatch.edgeAmbiguous},
        {"unexplained", m.idMismatch.unexplained}}},
      {"depth_compared", m.depthCompared},
      {"depth_beyond_tolerance", m.depthBeyondTolerance},
      {"depth_error_quanta", distribution(m.depthErrorQuanta, true)},
      {"distance_rel_error", distribution(m.distanceRelError, true)},
      {"tolerance_ratio", distribution(m.toleranceRatio, false)},
      {"by_kind", byKindJson(m)},
      {"verdict", runVerdictName(runVerdict(run))},
      {"convention_check", conventionCheckJson(run)},
      {"timings_ms", timingsJson(run.timings)},
      {"cpu_ms", timingsJson(run.cpu)},
      {"analytic_over_raster", number(run.analyticOverRaster)},
      {"images", imagesJson(run)},
      {"thumbnails", thumbnailsJson(run)},
      {"cluster_count", run.clusters.count},
      {"clusters", clustersJson(run)},
      {"worst_pixel", worstPixelJson(run)},
  };
  if (run.rounds > 1) {
    json["rounds"] = run.rounds;
    json["first_round_timings_ms"] = timingsJson(run.firstRound);
    json["first_round_cpu_ms"] = timingsJson(run.firstRoundCpu);
  }
  // Only where a scene sets it: reports of the default range read as before.
  if (run.depthRange != glm::dvec2(0.0, 1.0)) {
    json["depth_range"] = {run.depthRange.x, run.depthRange.y};
  }
  if (run.depthClamp) {
    json["depth_clamp"] = true;
    json["in_front_of_near"] = m.inFrontOfNear;
  }
  if (!run.polygonOffsets.empty()) {
    json["polygon_offsets"] = nlohmann::json::array();
    for (const OffsetRecord& o : run.polygonOffsets) {
      json["polygon_offsets"].push_back({{"object", o.object},
                                         {"factor", o.factor},
                                         {"units", o.units},
                                         {"clamp", o.clamp},
                                         {"pixels", o.pixels},
                                         {"predicted", {o.predictedLow, o.predictedHigh}},
                                         {"measured", {o.measuredMin, o.measuredMax}}});
    }
  }
  if (run.sample) {
    const SampleRecord& sample = *run.sample;
    const MultisamplePixels& p = sample.pixels;
    json["sample"] = {{"index", sample.index},
                      {"count", sample.count},
                      {"position", {sample.position.x, sample.position.y}},
                      {"frame_pixels",
                       {{"pixels", p.pixels},
                        {"covered", p.covered},
                        {"partly_covered", p.partlyCovered},
                        {"mixed_primitives", p.mixedPrimitives},
                        {"unexplained", p.unexplained}}}};
  }
  if (!run.notes.empty()) json["notes"] = run.notes;
  if (!run.capture.empty()) json["capture"] = run.capture;
  if (run.screenPath && !run.screenPath->declined.empty()) {
    json["screen_path"] = {{"declined", run.screenPath->declined}};
  } else if (run.screenPath) {
    const ScreenPathRecord& s = *run.screenPath;
    json["screen_path"] = {{"background", s.background},
                           {"decided", s.decided},
                           {"contested", s.contested},
                           {"traced", s.traced},
                           {"bound_misses", s.boundMisses},
                           {"ray_deviation_ndc", s.rayDeviationNdc},
                           {"compared_from_planes", s.comparedFromPlanes},
                           {"compared_along_rays", s.comparedAlongRays}};
    if (s.groups != 1) {
      json["screen_path"]["frames"] = s.frames;
      json["screen_path"]["groups"] = s.groups;
    }
  }
  return json;
}

std::int64_t unexplainedCount(const RunMetrics& m) {
  return m.coverageMismatch.unexplained + m.idMismatch.unexplained + m.depthBeyondTolerance;
}

// For ordering: NaN counts as the worst (largest) value.
double sortKey(double value) {
  return std::isnan(value) ? std::numeric_limits<double>::infinity() : value;
}

// Two significant digits, a short exponent ("2.1e-7", "1.2e5"); "nan" / "inf" spelled out.
std::string twoDigits(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2g", value);
  std::string text = buffer;
  const std::size_t e = text.find('e');
  if (e == std::string::npos) return text;
  std::string exponent = text.substr(e + 1);
  const bool negative = exponent.front() == '-';
  exponent.erase(0, exponent.find_first_not_of("+-"));
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return text.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

// The summary's columns: which run, then its figures (docs/reconcile.md, "The summary line"). Each
// column is as wide as its widest entry over the runs shown together (and its header); the
// figures' header spans the four figure columns: cov, id, >tol and the depth figures.
constexpr std::size_t kWhichColumns = 6;
constexpr std::size_t kSummaryColumns = kWhichColumns + 5;
using SummaryCells = std::array<std::string, kSummaryColumns>;
constexpr std::array<const char*, kWhichColumns + 1> kSummaryHeader{"verdict",
                                                                    "scene/camera",
                                                                    "convention",
                                                                    "fmt",
                                                                    "vertex mode",
                                                                    "size",
                                                                    "mismatches and depth error"};
constexpr const char* kSummaryLegend =
    "  cov: coverage mismatches (e edge-ambiguous, u unexplained); >tol: depths beyond "
    "tolerance\n"
    "  id: id mismatches (z depth-ambiguous, e edge-ambiguous, u unexplained)\n"
    "  tol: depth error / predicted tolerance, max/p99 (above 1: beyond it); rel: p99 distance "
    "error / eye distance\n"
    "  n/a (0 compared): no pixel where both sides hit the same primitive\n";

// Only under a summary that shows a run with findings of the convention check.
constexpr const char* kConventionLegend =
    "  check: clipray check on the run's camera under the state it is drawn with, its errors and "
    "warnings (expected: the scene declares it, expectedFindings); an error the scene does not "
    "expect is the verdict CONVENTION-ERROR\n";

// Only under a summary that shows a run drawn with depth clamp.
constexpr const char* kDepthClampLegend =
    "  front: pixels in front of the near plane, drawn by depth clamp at the near depth: out of "
    "reach of a picking ray that starts on the near plane\n";

std::string countText(std::int64_t value) {
  return std::to_string(static_cast<long long>(value));
}

SummaryCells summaryCells(const RunRecord& run) {
  const RunMetrics& m = run.metrics;
  const auto& c = m.coverageMismatch;
  const auto& i = m.idMismatch;
  const RunVerdict verdict = runVerdict(run);
  return {verdict == RunVerdict::Consistent     ? "consistent"
          : verdict == RunVerdict::Inconsistent ? "INCONSISTENT"
                                                : "CONVENTION-ERROR",
          run.scene + "/" + run.camera,
          run.convention.name(),
          depthFormatName(run.depthFormat),
          vertexModeName(run.vertexMode) + sampleSuffix(run),
          std::to_string(run.size.width) + "x" + std::to_string(run.size.height),
          "cov " + countText(c.total) + " (e" + countText(c.edgeAmbiguous) + " u" +
              countText(c.unexplained) + ")",
          "id " + countText(i.total) + " (z" + countText(i.depthAmbiguous) + " e" +
              countText(i.edgeAmbiguous) + " u" + countText(i.unexplained) + ")",
          ">tol " + countText(m.depthBeyondTolerance),
          depthFiguresText(m) +
              (run.depthClamp ? " front " + countText(m.inFrontOfNear) : std::string()),
          conventionNoteText(run)};
}

// The cells joined, each padded to its column's width, without trailing spaces.
std::string joinedCells(const std::vector<std::string>& cells,
                        const std::vector<std::size_t>& widths) {
  std::string line;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (k > 0) line += ' ';
    line += cells[k];
    if (k < widths.size() && cells[k].size() < widths[k]) {
      line.append(widths[k] - cells[k].size(), ' ');
    }
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line;
}

// The header and each run's line (in the order given), in columns sized to them.
std::vector<std::string> summaryTable(const std::vector<const RunRecord*>& runs) {
  std::vector<SummaryCells> rows;
  rows.reserve(runs.size());
  for (const RunRecord* run : runs) rows.push_back(summaryCells(*run));
  std::vector<std::size_t> widths(kSummaryColumns, 0);
  for (std::size_t k = 0; k < kWhichColumns; ++k) widths[k] = std::strlen(kSummaryHeader[k]);
  for (const SummaryCells& row : rows) {
    for (std::size_t k = 0; k < kSummaryColumns; ++k) {
      widths[k] = std::max(widths[k], row[k].size());
    }
  }
  std::vector<std::string> lines;
  lines.push_back(
      joinedCells(std::vector<std::string>(kSummaryHeader.begin(), kSummaryHeader.end()), widths));
  for (const SummaryCells& row : rows) {
    lines.push_back(joinedCells(std::vector<std::string>(row.begin(), row.end()), widths));
  }
  return lines;
}

// Which side hit what in each inconsistent run (in the order given): its worst pixel and its
// largest clusters' pixels.
std::string hitsSection(const std::vector<const RunRecord*>& runs) {
  std::string out;
  for (const RunRecord* run : runs) {
    if (run->metrics.consistent() || (!run->worstPixel && run->clusterHits.empty())) continue;
    if (out.empty()) {
      out =
          "which side hit what in the inconsistent runs (pixels in GL window coordinates, y up "
          "from the bottom row):\n";
    }
    out += "  " + runTitleText(*run) + "\n";
    out += runHitsText(*run, "    ");
  }
  return out;
}

// The findings of each run that fails for them (in the order given), whole, with their fixes.
std::string conventionErrorsSection(const std::vector<const RunRecord*>& runs) {
  std::string out;
  for (const RunRecord* run : runs) {
    if (runVerdict(*run) != RunVerdict::ConventionError) continue;
    if (out.empty()) {
      out =
          "convention errors the scenes do not expect (clipray check on the run's camera under "
          "the state it is drawn with):\n";
    }
    out += "  " + runTitleText(*run) + "\n";
    out += conventionFindingsText(*run, "    ");
  }
  return out;
}

}  // namespace

std::string SurfaceHit::name() const {
  if (!hit()) return "nothing";
  if (kind == "triangle") return "\"" + object + "\" triangle " + std::to_string(triangle);
  if (!kind.empty() && kind != "unknown") return "\"" + object + "\" (" + kind + ")";
  return "id " + std::to_string(id);
}

std::string SurfaceHit::text() const {
  if (!hit() || std::isnan(depth)) return name();
  return name() + " at depth " + sixDigits(depth);
}

std::string PixelHits::text() const {
  std::string out =
      std::string(pixelClassName(pixelClass)) + ": raster " + raster.text() + ", ray " + ray.text();
  if (!std::isnan(toleranceRatio)) out += ", error/tolerance " + twoDigits(toleranceRatio);
  return out;
}

std::string sampleSuffix(const RunRecord& run) {
  if (!run.sample) return "";
  return " sample " + std::to_string(run.sample->index) + " of " +
         std::to_string(run.sample->count);
}

std::string runTitleText(const RunRecord& run) {
  return run.scene + "/" + run.camera + " " + run.convention.name() + " " +
         depthFormatName(run.depthFormat) + " " + vertexModeName(run.vertexMode) +
         sampleSuffix(run);
}

RunVerdict runVerdict(const RunRecord& run) {
  if (!run.metrics.consistent()) return RunVerdict::Inconsistent;
  return unexpectedConventionErrors(run) > 0 ? RunVerdict::ConventionError : RunVerdict::Consistent;
}

const char* runVerdictName(RunVerdict verdict) {
  switch (verdict) {
    case RunVerdict::Consistent:
      return "consistent";
    case RunVerdict::Inconsistent:
      return "inconsistent";
    case RunVerdict::ConventionError:
      return "convention-error";
  }
  return "inconsistent";
}

std::size_t unexpectedConventionErrors(const RunRecord& run) {
  return static_cast<std::size_t>(
      std::count_if(run.conventionFindings.begin(), run.conventionFindings.end(),
                    [](const RunFinding& f) { return f.severity == "error" && !f.expected; }));
}

std::string conventionNoteText(const RunRecord& run) {
  std::string out;
  for (const RunFinding& f : run.conventionFindings) {
    out += (out.empty() ? "check " : ", ") + f.severity + ":" + f.code +
           (f.expected ? " (expected)" : "");
  }
  return out;
}

std::string conventionFindingsText(const RunRecord& run, const std::string& indent) {
  std::string out;
  for (const RunFinding& f : run.conventionFindings) {
    out += indent + f.severity + " [" + f.code + "] " + f.message +
           (f.expected ? " (expected by the scene)" : "") + "\n";
    if (!f.fix.empty()) out += indent + "  fix: " + f.fix + "\n";
  }
  return out;
}

std::string runHitsText(const RunRecord& run, const std::string& indent) {
  std::string out;
  if (run.worstPixel) {
    const PixelHits& p = *run.worstPixel;
    out += indent + "worst pixel (" + std::to_string(p.x) + ", " + std::to_string(p.y) +
           "): " + p.text() + "\n";
  }
  for (std::size_t k = 0; k < run.clusterHits.size() && k < run.clusters.largest.size(); ++k) {
    const MismatchCluster& c = run.clusters.largest[k];
    out += indent + "cluster " + std::to_string(k + 1) + " (" + std::to_string(c.pixels) +
           " px) at (" + std::to_string(c.x) + ", " + std::to_string(c.y) +
           "): " + run.clusterHits[k].text() + "\n";
  }
  return out;
}

std::string depthFiguresText(const RunMetrics& m) {
  if (m.depthCompared == 0) return "depth n/a (0 compared)";
  return "tol " + twoDigits(m.toleranceRatio.max) + "/" + twoDigits(m.toleranceRatio.p99) +
         " rel " + twoDigits(m.distanceRelError.p99);
}

std::vector<std::string> runSummaryLines(const std::vector<RunRecord>& runs) {
  std::vector<const RunRecord*> shown;
  for (const RunRecord& run : runs) shown.push_back(&run);
  std::vector<std::string> lines = summaryTable(shown);
  lines.erase(lines.begin());
  return lines;
}

std::string runSummaryLine(const RunRecord& run) {
  return summaryTable({&run}).back();
}

std::string shortNumber(double value) {
  return twoDigits(value);
}

std::string pathComponent(const std::string& name) {
  std::string out;
  out.reserve(name.size());
  for (const char c : name) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '.' || c == '_' || c == '+' || c == '-';
    out.push_back(safe ? c : '_');
  }
  if (out.find_first_not_of('.') == std::string::npos)
    std::replace(out.begin(), out.end(), '.', '_');
  if (out.empty()) out = "_";
  return out;
}

void checkDistinctRunFolders(const std::vector<const Scene*>& scenes) {
  std::map<std::string, const Scene*> sceneByFolder;
  for (const Scene* planned : scenes) {
    const Scene& scene = *planned;
    const std::string folder = pathComponent(scene.name);
    const auto [seen, inserted] = sceneByFolder.emplace(folder, &scene);
    if (!inserted) {
      throw InputError(seen->second->path + " and " + scene.path +
                       ": both would write their runs under the report folder \"" + folder +
                       "/\" (scene names \"" + seen->second->name + "\" and \"" + scene.name +
                       "\"); reconcile them separately, or rename one");
    }
    std::map<std::string, const std::string*> cameraByFolder;
    for (const Camera& camera : scene.cameras) {
      const std::string cameraFolder = pathComponent(camera.name);
      const auto [other, fresh] = cameraByFolder.emplace(cameraFolder, &camera.name);
      if (!fresh) {
        throw InputError(scene.path + ": cameras \"" + *other->second + "\" and \"" + camera.name +
                         "\" would share the report folders \"" + folder + "/" + cameraFolder +
                         "-...\"; rename one");
      }
    }
  }
}

std::string runFolderName(const RunRecord& run) {
  return pathComponent(run.scene) + "/" + pathComponent(run.camera) + "-" + run.convention.name() +
         "-" + depthFormatName(run.depthFormat) + "-" + vertexModeName(run.vertexMode) +
         (run.sample
              ? "-s" + std::to_string(run.sample->index) + "of" + std::to_string(run.sample->count)
              : std::string());
}

nlohmann::json reportJson(const std::vector<RunRecord>& runs, const GlInfo& gl,
                          const ReportProvenance& provenance) {
  nlohmann::json runList = nlohmann::json::array();
  std::int64_t consistent = 0, conventionErrors = 0;
  for (const RunRecord& run : runs) {
    runList.push_back(runJson(run));
    const RunVerdict verdict = runVerdict(run);
    if (verdict == RunVerdict::Consistent) ++consistent;
    if (verdict == RunVerdict::ConventionError) ++conventionErrors;
  }
  const auto total = static_cast<std::int64_t>(runs.size());
  nlohmann::json report = {
      {"tool", "clipray"},
      {"format_version", 1},
      {"clipray_version", versionNumber()},
      {"git_commit", gitCommit()},
      {"gl",
       {{"backend", gl.backend},
        {"vendor", gl.vendor},
        {"renderer", gl.renderer},
        {"version", gl.version},
        {"subpixel_bits", gl.subpixelBits}}},
      {"summary",
       {{"runs", total},
        {"consistent", consistent},
        {"inconsistent", total - consistent - conventionErrors},
        {"convention_error", conventionErrors},
        {"verdict", consistent == total                      ? "consistent"
                    : consistent + conventionErrors == total ? "convention-error"
                                                             : "inconsistent"}}},
      {"runs", std::move(runList)},
  };
  if (!provenance.commandLine.empty()) report["command_line"] = provenance.commandLine;
  if (!provenance.startedAt.empty()) report["started_at"] = provenance.startedAt;
  if (provenance.shardCount > 0) {
    report["shard"] = {{"index", provenance.shardIndex}, {"count", provenance.shardCount}};
  }
  return report;
}

namespace {

// The median of values; NaN if any is NaN (a timing that failed to measure).
double median(std::vector<double> values) {
  if (std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); })) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Each timing's median.
RunTimings medianTimings(const std::vector<RunTimings>& timings) {
  const auto medianOf = [&](double RunTimings::*field) {
    std::vector<double> values;
    for (const RunTimings& t : timings) values.push_back(t.*field);
    return median(std::move(values));
  };
  return {medianOf(&RunTimings::raster), medianOf(&RunTimings::readback),
          medianOf(&RunTimings::rays), medianOf(&RunTimings::intersect),
          medianOf(&RunTimings::compare)};
}

// What a run measured, less its timings and images: the same in every round.
nlohmann::json measuredJson(const RunRecord& run) {
  nlohmann::json json = runJson(run);
  for (const char* timed :
       {"timings_ms", "cpu_ms", "analytic_over_raster", "rounds", "first_round_timings_ms",
        "first_round_cpu_ms", "images", "thumbnails"}) {
    json.erase(timed);
  }
  for (nlohmann::json& cluster : json["clusters"]) cluster.erase("crop");
  return json;
}

}  // namespace

std::vector<RunRecord> mergeRounds(std::vector<std::vector<RunRecord>> rounds) {
  CLIPRAY_CHECK(!rounds.empty(), "mergeRounds: no rounds");
  for (const std::vector<RunRecord>& round : rounds) {
    bool same = round.size() == rounds.front().size();
    for (std::size_t i = 0; same && i < round.size(); ++i) {
      same = runFolderName(round[i]) == runFolderName(rounds.front()[i]);
    }
    CLIPRAY_CHECK(same, "mergeRounds: the rounds made different runs");
  }
  std::vector<RunRecord> runs = std::move(rounds.back());
  if (rounds.size() == 1) return runs;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    // Rendering and tracing are deterministic: a round that measured a run differently is a bug
    // to hear about, not a figure to drop.
    const nlohmann::json measured = measuredJson(runs[i]);
    for (std::size_t r = 0; r + 1 < rounds.size(); ++r) {
      if (measuredJson(rounds[r][i]) != measured) {
        throw std::runtime_error(runFolderName(runs[i]) + ": round " + std::to_string(r + 1) +
                                 " measured it differently from round " +
                                 std::to_string(rounds.size()) +
                                 " (a nondeterministic renderer or a clipray bug)");
      }
    }
    // Rounds 2.. (the last round's record was moved into runs).
    const auto roundRecord = [&](std::size_t r) -> const RunRecord& {
      return r + 1 == rounds.size() ? runs[i] : rounds[r][i];
    };
    std::vector<RunTimings> timings, cpu;
    std::vector<double> ratio;
    for (std::size_t r = 1; r < rounds.size(); ++r) {
      timings.push_back(roundRecord(r).timings);
      cpu.push_back(roundRecord(r).cpu);
      ratio.push_back(roundRecord(r).timings.analyticOverRaster());
    }
    RunRecord& run = runs[i];
    run.rounds = static_cast<int>(rounds.size());
    run.firstRound = rounds.front()[i].timings;
    run.firstRoundCpu = rounds.front()[i].cpu;
    run.timings = medianTimings(timings);
    run.cpu = medianTimings(cpu);
    run.analyticOverRaster = median(ratio);
  }
  return runs;
}

std::vector<std::size_t> worstFirst(const std::vector<RunRecord>& runs) {
  std::vector<std::size_t> order(runs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const RunMetrics& ma = runs[a].metrics;
    const RunMetrics& mb = runs[b].metrics;
    if (ma.consistent() != mb.consistent()) return !ma.consistent();
    // Then the runs that fail for their camera's convention check.
    const bool ea = runVerdict(runs[a]) == RunVerdict::ConventionError;
    const bool eb = runVerdict(runs[b]) == RunVerdict::ConventionError;
    if (ea != eb) return ea;
    const std::int64_t ua = unexplainedCount(ma), ub = unexplainedCount(mb);
    if (ua != ub) return ua > ub;
    return sortKey(ma.toleranceRatio.max) > sortKey(mb.toleranceRatio.max);
  });
  return order;
}

std::string textSummary(const std::vector<RunRecord>& runs) {
  std::vector<const RunRecord*> shown;
  std::size_t consistent = 0, conventionErrors = 0;
  for (const std::size_t i : worstFirst(runs)) {
    shown.push_back(&runs[i]);
    const RunVerdict verdict = runVerdict(runs[i]);
    if (verdict == RunVerdict::Consistent) ++consistent;
    if (verdict == RunVerdict::ConventionError) ++conventionErrors;
  }
  std::string out;
  if (!runs.empty()) {
    for (const std::string& line : summaryTable(shown)) out += line + "\n";
  }
  out += std::to_string(runs.size()) + " runs: " + std::to_string(consistent) + " consistent, " +
         std::to_string(runs.size() - consistent - conventionErrors) + " inconsistent";
  // Only where there are any: a summary without them reads as before.
  if (conventionErrors > 0) {
    out += ", " + std::to_string(conventionErrors) + " convention error" +
           (conventionErrors == 1 ? "" : "s");
  }
  out += "\n";
  out += hitsSection(shown);
  out += conventionErrorsSection(shown);
  if (!runs.empty()) out += kSummaryLegend;
  if (std::any_of(runs.begin(), runs.end(),
                  [](const RunRecord& r) { return !r.conventionFindings.empty(); })) {
    out += kConventionLegend;
  }
  if (std::any_of(runs.begin(), runs.end(), [](const RunRecord& r) { return r.depthClamp; })) {
    out += kDepthClampLegend;
  }
  return out;
}

}  // namespace clipray

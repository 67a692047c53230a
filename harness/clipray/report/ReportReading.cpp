#include "clipray/report/ReportReading.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "clipray/InputError.hpp"
#include "clipray/io/InputFile.hpp"
#include "clipray/io/LocatedJson.hpp"

namespace clipray {

namespace {

using detail::json;
using detail::Pointer;

constexpr std::array<PixelClass, 9> kPixelClasses{
    PixelClass::Background,           PixelClass::Agree,
    PixelClass::DepthBeyondTolerance, PixelClass::CoverageEdgeAmbiguous,
    PixelClass::CoverageUnexplained,  PixelClass::IdDepthAmbiguous,
    PixelClass::IdEdgeAmbiguous,      PixelClass::IdUnexplained,
    PixelClass::InFrontOfNear};

// A report.json holds every run of a run's images beside it; PNGs are read back whole.
constexpr std::uint64_t kMaxReportBytes = 1ull << 30;
constexpr std::uint64_t kMaxImageBytes = 1ull << 30;

class ReportReader {
 public:
  ReportReader(std::filesystem::path folder, std::string file)
      : folder_(std::move(folder)), file_(std::move(file)) {}

  [[noreturn]] void fail(const Pointer& at, const std::string& message) const {
    throw InputError(file_, detail::pointerText(at), message);
  }

  const json& field(const json& object, const Pointer& at, const char* key) const {
    if (!object.is_object()) fail(at, "expected an object, got " + detail::describe(object));
    const auto found = object.find(key);
    if (found == object.end()) fail(at, std::string("missing field \"") + key + "\"");
    return *found;
  }

  std::string text(const json& object, const Pointer& at, const char* key) const {
    const json& value = field(object, at, key);
    if (!value.is_string()) fail(at / key, "expected a string, got " + detail::describe(value));
    return value.get<std::string>();
  }

  std::int64_t integer(const json& object, const Pointer& at, const char* key) const {
    const json& value = field(object, at, key);
    if (!value.is_number_integer()) {
      fail(at / key, "expected an integer, got " + detail::describe(value));
    }
    return value.get<std::int64_t>();
  }

  // A number, or null for what JSON cannot spell (NaN).
  double figure(const json& object, const Pointer& at, const char* key) const {
    const json& value = field(object, at, key);
    if (value.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!value.is_number()) {
      fail(at / key, "expected a number or null, got " + detail::describe(value));
    }
    return value.get<double>();
  }

  Distribution distribution(const json& object, const Pointer& at, const char* key,
                            bool withP50) const {
    const json& value = field(object, at, key);
    Distribution d;
    d.max = figure(value, at / key, "max");
    d.p99 = figure(value, at / key, "p99");
    if (withP50) d.p50 = figure(value, at / key, "p50");
    return d;
  }

  RunTimings timings(const json& object, const Pointer& at, const char* key) const {
    const json& value = field(object, at, key);
    const Pointer t = at / key;
    return {figure(value, t, "raster"), figure(value, t, "readback"), figure(value, t, "rays"),
            figure(value, t, "intersect"), figure(value, t, "compare")};
  }

  // An image the report names (a path relative to its folder), or nothing for null.
  void image(const json& object, const Pointer& at, const char* key, RunRecord& run) const {
    const json& value = field(object, at, key);
    if (value.is_null()) return;
    if (!value.is_string()) {
      fail(at / key, "expected an image path or null, got " + detail::describe(value));
    }
    const std::string relative = value.get<std::string>();
    const std::filesystem::path path(relative);
    if (relative.empty() || path.is_absolute() ||
        std::any_of(path.begin(), path.end(), [](const auto& part) { return part == ".."; })) {
      fail(at / key, "expected a path inside the report's folder, got " + detail::describe(value));
    }
    const std::filesystem::path file = folder_ / path;
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) {
      fail(at / key, "names " + relative + ", which is not in " + folder_.string());
    }
    run.images.push_back({relative, readInputFile(file.string(), kMaxImageBytes, "image")});
  }

  // What one side hit (hitJson): null for nothing.
  SurfaceHit hit(const json& object, const Pointer& at, const char* key) const {
    const json& value = field(object, at, key);
    SurfaceHit out;
    if (value.is_null()) return out;
    const Pointer hAt = at / key;
    const std::int64_t id = integer(value, hAt, "id");
    if (id < 1 || id > std::numeric_limits<std::uint32_t>::max()) {
      fail(hAt / "id", "expected a primitive id from 1, got " + std::to_string(id));
    }
    out.id = static_cast<std::uint32_t>(id);
    out.object = text(value, hAt, "object");
    out.kind = text(value, hAt, "kind");
    out.triangle = field(value, hAt, "triangle").is_null() ? -1 : integer(value, hAt, "triangle");
    out.depth = figure(value, hAt, "depth");
    return out;
  }

  // A pixel's class, both sides' hits and the error / tolerance (addHitsJson).
  PixelHits pixelHits(const json& object, const Pointer& at, int x, int y) const {
    PixelHits out;
    out.x = x;
    out.y = y;
    const std::string name = text(object, at, "class");
    const auto known = std::find_if(kPixelClasses.begin(), kPixelClasses.end(),
                                    [&](PixelClass c) { return name == pixelClassName(c); });
    if (known == kPixelClasses.end()) {
      fail(at / "class",
           "expected a pixel class (e.g. coverage_unexplained), got \"" + name + "\"");
    }
    out.pixelClass = *known;
    out.raster = hit(object, at, "raster");
    out.ray = hit(object, at, "ray");
    out.toleranceRatio = figure(object, at, "tolerance_ratio");
    return out;
  }

  // The convention check's findings (conventionCheckJson): errors and warnings.
  std::vector<RunFinding> conventionFindings(const json& value, const Pointer& at) const {
    if (!value.is_array()) fail(at, "expected an array, got " + detail::describe(value));
    std::vector<RunFinding> findings;
    for (std::size_t k = 0; k < value.size(); ++k) {
      const json& f = value[k];
      const Pointer fAt = at / k;
      RunFinding finding;
      finding.severity = text(f, fAt, "severity");
      if (finding.severity != "error" && finding.severity != "warning") {
        fail(fAt / "severity",
             "expected \"error\" or \"warning\", got " + detail::describe(f["severity"]));
      }
      finding.code = text(f, fAt, "code");
      finding.message = text(f, fAt, "message");
      finding.fix = text(f, fAt, "fix");
      const json& expected = field(f, fAt, "expected");
      if (!expected.is_boolean()) {
        fail(fAt / "expected", "expected true or false, got " + detail::describe(expected));
      }
      finding.expected = expected.get<bool>();
      findings.push_back(std::move(finding));
    }
    return findings;
  }

  DepthMode convention(const json& object, const Pointer& at) const {
    const std::string name = text(object, at, "convention");
    const std::optional<DepthMode> mode = DepthMode::parse(name);
    if (!mode) {
      fail(at / "convention",
           "expected no, zo or zo-reversed (each also with -upper-left), got \"" + name + "\"");
    }
    return *mode;
  }

  RunRecord run(const json& value, const Pointer& at) const {
    RunRecord run;
    run.scene = text(value, at, "scene");
    run.camera = text(value, at, "camera");
    run.convention = convention(value, at);
    const std::string format = text(value, at, "depth_format");
    const std::optional<DepthFormat> depthFormat = parseDepthFormat(format);
    if (!depthFormat) fail(at / "depth_format", "expected 16, 24 or 32f, got \"" + format + "\"");
    run.depthFormat = *depthFormat;
    const std::string vertex = text(value, at, "vertex_mode");
    const std::optional<VertexMode> vertexMode = parseVertexMode(vertex);
    if (!vertexMode) fail(at / "vertex_mode", "expected a vertex mode, got \"" + vertex + "\"");
    run.vertexMode = *vertexMode;
    if (value.contains("depth_range")) {
      const json& range = value["depth_range"];
      if (!range.is_array() || range.size() != 2 || !range[0].is_number() ||
          !range[1].is_number()) {
        fail(at / "depth_range", "expected [near, far], got " + range.dump());
      }
      run.depthRange = {range[0].get<double>(), range[1].get<double>()};
    }
    if (value.contains("depth_clamp")) {
      if (!value["depth_clamp"].is_boolean()) {
        fail(at / "depth_clamp", "expected true or false, got " + value["depth_clamp"].dump());
      }
      run.depthClamp = value["depth_clamp"].get<bool>();
    }
    if (value.contains("polygon_offsets")) {
      const json& offsets = value["polygon_offsets"];
      if (!offsets.is_array()) {
        fail(at / "polygon_offsets", "expected an array, got " + offsets.dump());
      }
      for (std::size_t k = 0; k < offsets.size(); ++k) {
        const json& o = offsets[k];
        const Pointer oAt = at / "polygon_offsets" / std::to_string(k);
        const auto pair = [&](const char* key) {
          if (!o.contains(key) || !o[key].is_array() || o[key].size() != 2 ||
              !o[key][0].is_number() || !o[key][1].is_number()) {
            fail(oAt / key, "expected [low, high]");
          }
          return glm::dvec2(o[key][0].get<double>(), o[key][1].get<double>());
        };
        const auto scalar = [&](const char* key) {
          if (!o.contains(key) || !o[key].is_number()) fail(oAt / key, "expected a number");
          return o[key].get<double>();
        };
        if (!o.contains("object") || !o["object"].is_string()) {
          fail(oAt / "object", "expected a string");
        }
        const glm::dvec2 predicted = pair("predicted"), measured = pair("measured");
        run.polygonOffsets.push_back({o["object"].get<std::string>(), scalar("factor"),
                                      scalar("units"), scalar("clamp"),
                                      static_cast<std::int64_t>(scalar("pixels")), predicted.x,
                                      predicted.y, measured.x, measured.y});
      }
    }
    if (value.contains("sample")) {
      const json& sample = value["sample"];
      const Pointer sAt = at / "sample";
      SampleRecord record;
      record.index = static_cast<int>(integer(sample, sAt, "index"));
      record.count = static_cast<int>(integer(sample, sAt, "count"));
      if (!sample.contains("position") || !sample["position"].is_array() ||
          sample["position"].size() != 2 || !sample["position"][0].is_number() ||
          !sample["position"][1].is_number()) {
        fail(sAt / "position", "expected [x, y]");
      }
      record.position = {sample["position"][0].get<double>(), sample["position"][1].get<double>()};
      const json& p = field(sample, sAt, "frame_pixels");
      const Pointer pAt = sAt / "frame_pixels";
      record.pixels = {integer(p, pAt, "pixels"), integer(p, pAt, "covered"),
                       integer(p, pAt, "partly_covered"), integer(p, pAt, "mixed_primitives"),
                       integer(p, pAt, "unexplained")};
      run.sample = record;
    }
    if (value.contains("notes")) {
      const json& notes = value["notes"];
      if (!notes.is_array())
        fail(at / "notes", "expected an array of strings, got " + notes.dump());
      for (std::size_t i = 0; i < notes.size(); ++i) {
        if (!notes[i].is_string()) {
          fail(at / "notes" / i, "expected a string, got " + notes[i].dump());
        }
        run.notes.push_back(notes[i].get<std::string>());
      }
    }
    if (value.contains("screen_path")) {
      // What the screen path did with the frame: its counts, or why it declined it.
      const json& path = value["screen_path"];
      const Pointer pAt = at / "screen_path";
      if (!path.is_object()) fail(pAt, "expected an object, got " + detail::describe(path));
      ScreenPathRecord record;
      if (path.contains("declined")) {
        record.declined = text(path, pAt, "declined");
      } else {
        record.background = integer(path, pAt, "background");
        record.decided = integer(path, pAt, "decided");
        record.contested = integer(path, pAt, "contested");
        record.traced = integer(path, pAt, "traced");
        record.boundMisses = integer(path, pAt, "bound_misses");
        record.rayDeviationNdc = figure(path, pAt, "ray_deviation_ndc");
        // Reports written before the compare took planes have no such counts.
        if (path.contains("compared_from_planes") || path.contains("compared_along_rays")) {
          record.comparedFromPlanes = integer(path, pAt, "compared_from_planes");
          record.comparedAlongRays = integer(path, pAt, "compared_along_rays");
        }
        // Frames of objects drawn in groups of their own state: a frame per group evaluated.
        if (path.contains("groups")) {
          record.frames = integer(path, pAt, "frames");
          record.groups = integer(path, pAt, "groups");
        }
      }
      run.screenPath = record;
    }
    const json& size = field(value, at, "size");
    run.size = {static_cast<int>(integer(size, at / "size", "width")),
                static_cast<int>(integer(size, at / "size", "height"))};

    RunMetrics& m = run.metrics;
    m.pixels = integer(value, at, "pixels");
    m.rasterHits = integer(value, at, "raster_hits");
    m.rayHits = integer(value, at, "ray_hits");
    const json& coverage = field(value, at, "coverage_mismatch");
    const Pointer cAt = at / "coverage_mismatch";
    m.coverageMismatch = {integer(coverage, cAt, "total"), integer(coverage, cAt, "edge_ambiguous"),
                          integer(coverage, cAt, "unexplained")};
    const json& id = field(value, at, "id_mismatch");
    const Pointer iAt = at / "id_mismatch";
    m.idMismatch = {integer(id, iAt, "total"), integer(id, iAt, "depth_ambiguous"),
                    integer(id, iAt, "edge_ambiguous"), integer(id, iAt, "unexplained")};
    m.depthCompared = integer(value, at, "depth_compared");
    m.depthBeyondTolerance = integer(value, at, "depth_beyond_tolerance");
    if (run.depthClamp) m.inFrontOfNear = integer(value, at, "in_front_of_near");
    m.depthErrorQuanta = distribution(value, at, "depth_error_quanta", true);
    m.distanceRelError = distribution(value, at, "distance_rel_error", true);
    m.toleranceRatio = distribution(value, at, "tolerance_ratio", false);
    const json& kinds = field(value, at, "by_kind");
    if (!kinds.is_object())
      fail(at / "by_kind", "expected an object, got " + detail::describe(kinds));
    for (const auto& [kind, figures] : kinds.items()) {
      const Pointer kAt = at / "by_kind" / kind;
      RunMetrics::KindFigures k;
      k.kind = kind;
      k.depthCompared = integer(figures, kAt, "depth_compared");
      k.depthErrorQuanta = distribution(figures, kAt, "depth_error_quanta", true);
      k.distanceRelError = distribution(figures, kAt, "distance_rel_error", true);
      k.toleranceRatio = distribution(figures, kAt, "tolerance_ratio", false);
      m.byKind.push_back(std::move(k));
    }
    // Reports written before runs carried their camera's check have none.
    if (value.contains("convention_check")) {
      run.conventionFindings =
          conventionFindings(value["convention_check"], at / "convention_check");
    }
    const std::string verdict = text(value, at, "verdict");
    if (verdict != runVerdictName(runVerdict(run))) {
      fail(at / "verdict",
           "\"" + verdict + "\" does not follow from the run's counts and convention check");
    }

    run.timings = timings(value, at, "timings_ms");
    run.cpu = timings(value, at, "cpu_ms");
    run.analyticOverRaster = figure(value, at, "analytic_over_raster");
    if (value.contains("rounds")) {
      run.rounds = static_cast<int>(integer(value, at, "rounds"));
      run.firstRound = timings(value, at, "first_round_timings_ms");
      run.firstRoundCpu = timings(value, at, "first_round_cpu_ms");
    }

    const json& images = field(value, at, "images");
    for (const char* name : {"raster_depth", "ray_depth", "error_heatmap", "mismatch"}) {
      image(images, at / "images", name, run);
    }
    const json& thumbnails = field(value, at, "thumbnails");
    image(thumbnails, at / "thumbnails", "mismatch", run);
    image(thumbnails, at / "thumbnails", "heatmap", run);

    run.clusters.count = integer(value, at, "cluster_count");
    const json& clusters = field(value, at, "clusters");
    if (!clusters.is_array()) {
      fail(at / "clusters", "expected an array, got " + detail::describe(clusters));
    }
    for (std::size_t k = 0; k < clusters.size(); ++k) {
      const json& c = clusters[k];
      const Pointer kAt = at / "clusters" / k;
      MismatchCluster cluster;
      cluster.pixels = integer(c, kAt, "pixels");
      cluster.coverageUnexplained = integer(c, kAt, "coverage_unexplained");
      cluster.idUnexplained = integer(c, kAt, "id_unexplained");
      cluster.depthBeyondTolerance = integer(c, kAt, "depth_beyond_tolerance");
      const json& pixel = field(c, kAt, "pixel_gl");
      cluster.x = static_cast<int>(integer(pixel, kAt / "pixel_gl", "x"));
      cluster.y = static_cast<int>(integer(pixel, kAt / "pixel_gl", "y"));
      const json& bounds = field(c, kAt, "bounds_gl");
      const Pointer bAt = kAt / "bounds_gl";
      cluster.minX = static_cast<int>(integer(bounds, bAt, "x_min"));
      cluster.minY = static_cast<int>(integer(bounds, bAt, "y_min"));
      cluster.maxX = static_cast<int>(integer(bounds, bAt, "x_max"));
      cluster.maxY = static_cast<int>(integer(bounds, bAt, "y_max"));
      image(c, kAt, "crop", run);
      run.clusters.largest.push_back(cluster);
      // Reports before which-side-hit-what have no hits.
      if (c.contains("class")) run.clusterHits.push_back(pixelHits(c, kAt, cluster.x, cluster.y));
    }
    if (!run.clusterHits.empty() && run.clusterHits.size() != run.clusters.largest.size()) {
      fail(at / "clusters", "expected what each side hit at every cluster's pixel or at none");
    }
    if (value.contains("worst_pixel") && !value["worst_pixel"].is_null()) {
      const json& worst = value["worst_pixel"];
      const Pointer wAt = at / "worst_pixel";
      const json& pixel = field(worst, wAt, "pixel_gl");
      run.worstPixel =
          pixelHits(worst, wAt, static_cast<int>(integer(pixel, wAt / "pixel_gl", "x")),
                    static_cast<int>(integer(pixel, wAt / "pixel_gl", "y")));
    }
    return run;
  }

  ReadReport report(const json& root) const {
    const Pointer top;
    ReadReport report;
    report.folder = folder_;
    const auto tool = root.is_object() ? root.find("tool") : root.end();
    if (!root.is_object() || tool == root.end() || *tool != "clipray") {
      fail(top, "not a clipray report (expected \"tool\": \"clipray\")");
    }
    if (integer(root, top, "format_version") != 1) {
      fail(top / "format_version",
           "this clipray reads format 1, got " + detail::describe(root["format_version"]));
    }
    report.version = text(root, top, "clipray_version");
    report.gitCommit = text(root, top, "git_commit");
    const json& gl = field(root, top, "gl");
    report.gl = {text(gl, top / "gl", "backend"), text(gl, top / "gl", "vendor"),
                 text(gl, top / "gl", "renderer"), text(gl, top / "gl", "version"),
                 static_cast<int>(integer(gl, top / "gl", "subpixel_bits"))};
    if (root.contains("command_line"))
      report.provenance.commandLine = text(root, top, "command_line");
    if (root.contains("started_at")) report.provenance.startedAt = text(root, top, "started_at");
    if (root.contains("shard")) {
      const json& shard = root["shard"];
      report.provenance.shardIndex = static_cast<int>(integer(shard, top / "shard", "index"));
      report.provenance.shardCount = static_cast<int>(integer(shard, top / "shard", "count"));
      if (report.provenance.shardCount < 1 || report.provenance.shardIndex < 1 ||
          report.provenance.shardIndex > report.provenance.shardCount) {
        fail(top / "shard", "expected 1 <= index <= count, got " + detail::describe(shard));
      }
    }
    const json& runs = field(root, top, "runs");
    if (!runs.is_array()) fail(top / "runs", "expected an array, got " + detail::describe(runs));
    for (std::size_t i = 0; i < runs.size(); ++i)
      report.runs.push_back(run(runs[i], top / "runs" / i));
    return report;
  }

 private:
  std::filesystem::path folder_;
  std::string file_;
};

std::string runKey(const RunRecord& run) {
  return runTitleText(run);
}

std::string reportFile(const ReadReport& report) {
  return (report.folder / "report.json").string();
}

}  // namespace

ReadReport readReport(const std::filesystem::path& folder) {
  const std::string file = (folder / "report.json").string();
  return parseReport(readInputFile(file, kMaxReportBytes, "report"), folder, file);
}

ReadReport parseReport(const std::string& text, const std::filesystem::path& folder,
                       const std::string& file) {
  return ReportReader(folder, file).report(detail::parseJson(text, file));
}

std::vector<RunRecord> mergeReports(const std::vector<ReadReport>& reports) {
  if (reports.empty()) throw InputError("report merge: expected at least one report folder");
  const ReadReport& first = reports.front();
  const auto differ = [&](const ReadReport& other, const std::string& what, const std::string& a,
                          const std::string& b) {
    throw InputError(reportFile(other) + ": " + what + " \"" + b + "\", but " + reportFile(first) +
                     " has \"" + a + "\": reports of different " +
                     (what == "GL renderer" ? "GL drivers" : "clipray builds") + " are not merged");
  };
  std::map<int, const ReadReport*> shards;
  std::map<std::string, const ReadReport*> runs;
  std::vector<RunRecord> merged;
  for (const ReadReport& report : reports) {
    if (report.version != first.version)
      differ(report, "clipray version", first.version, report.version);
    if (report.gitCommit != first.gitCommit)
      differ(report, "git commit", first.gitCommit, report.gitCommit);
    const std::string glA = first.gl.backend + " " + first.gl.renderer + " " + first.gl.version;
    const std::string glB = report.gl.backend + " " + report.gl.renderer + " " + report.gl.version;
    if (glA != glB) differ(report, "GL renderer", glA, glB);
    const ReportProvenance& p = report.provenance;
    if (p.shardCount != first.provenance.shardCount) {
      const auto shardText = [](const ReportProvenance& q) {
        return q.shardCount == 0
                   ? std::string("no shard")
                   : "shard " + std::to_string(q.shardIndex) + "/" + std::to_string(q.shardCount);
      };
      throw InputError(reportFile(report) + ": holds " + shardText(p) + ", but " +
                       reportFile(first) + " holds " + shardText(first.provenance) +
                       ": shards of one split have the same count");
    }
    if (p.shardCount > 0) {
      const auto [seen, fresh] = shards.emplace(p.shardIndex, &report);
      if (!fresh) {
        throw InputError(reportFile(report) + " and " + reportFile(*seen->second) +
                         ": both hold shard " + std::to_string(p.shardIndex) + "/" +
                         std::to_string(p.shardCount));
      }
    }
    for (const RunRecord& run : report.runs) {
      const auto [seen, fresh] = runs.emplace(runKey(run), &report);
      if (!fresh) {
        throw InputError(reportFile(report) + " and " + reportFile(*seen->second) +
                         ": both hold the run " + runKey(run));
      }
      merged.push_back(run);
    }
  }
  const int count = first.provenance.shardCount;
  if (count > 0 && static_cast<int>(shards.size()) != count) {
    std::string missing;
    for (int i = 1; i <= count; ++i) {
      if (!shards.contains(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
    }
    throw InputError("report merge: shards " + missing + " of " + std::to_string(count) +
                     " are missing (a merge of a split takes all of its shards)");
  }
  return merged;
}

}  // namespace clipray

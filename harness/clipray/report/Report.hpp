#pragma once
// The outputs of `clipray reconcile`: report.json (stable field names), a one-screen text summary,
// index.html (HtmlReport.hpp), and the PNGs of each run (RunImages.hpp). Files are written
// atomically (temp file in the same folder, then rename), and only after every run has finished, so
// a failed reconcile leaves nothing half-written.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/compare/MismatchClusters.hpp"
#include "clipray/compare/Reconcile.hpp"

namespace clipray {

struct RunTimings {  // milliseconds
  double raster = 0, readback = 0, rays = 0, intersect = 0, compare = 0;
  // What clipray adds to the raster pass it checks, relative to it: (rays + intersect + compare)
  // / raster.
  double analyticOverRaster() const { return (rays + intersect + compare) / raster; }
};

struct GlInfo {
  std::string backend;  // "osmesa", "egl"
  std::string vendor, renderer, version;
  int subpixelBits = 0;
};

// A PNG already encoded in memory, with its path relative to the output folder.
struct EncodedImage {
  std::string relativePath;
  std::string pngBytes;
};

// What one side of a run hit at a pixel: a triangle of a named object, an analytic primitive, or
// nothing (named by the engine from the scene: engine/WorstPixels.hpp).
struct SurfaceHit {
  std::uint32_t id = 0;  // the primitive id in the frames; 0: nothing
  std::string object;    // the object's or the analytic primitive's name
  std::string kind;      // "triangle", or the primitive's kind ("sphere", ...); empty: nothing
  std::int64_t triangle = -1;  // the triangle's index in its object; -1 for anything else
  double depth = std::numeric_limits<double>::quiet_NaN();  // window depth; NaN: none
  bool hit() const { return id != 0; }
  // "\"floor\" triangle 12", "\"ball\" (sphere)", "nothing"; "id 7" for an id the scene lacks.
  std::string name() const;
  // The name and the depth: "\"floor\" triangle 12 at depth 0.499871".
  std::string text() const;
  friend bool operator==(const SurfaceHit&, const SurfaceHit&) = default;
};

// Both sides at one pixel of a run.
struct PixelHits {
  int x = 0, y = 0;  // GL window coordinates: y from the bottom row
  PixelClass pixelClass = PixelClass::Background;
  SurfaceHit raster, ray;
  double toleranceRatio = std::numeric_limits<double>::quiet_NaN();  // NaN: not compared
  // "coverage_unexplained: raster nothing, ray \"wall\" triangle 3 at depth 0.999981", and
  // ", error/tolerance 3.2" where the depths were compared.
  std::string text() const;
};

// A finding of `clipray check` on the run's camera under the state the run is drawn with (its
// clip control, reversed-Z, depth range, face culling, depth clamp; engine/RunConventionCheck):
// errors and warnings only.
struct RunFinding {
  std::string severity;  // "error" or "warning"
  std::string code;      // the check's code: "depth-convention-mismatch", ...
  std::string message;
  std::string fix;
  bool expected = false;  // the scene declares it (its camera's expectedFindings)
  friend bool operator==(const RunFinding&, const RunFinding&) = default;
};

// An object drawn with a polygon offset (MeshObject::polygonOffset), over the pixels where both
// sides show it: the offsets GL allows there (the least low end and the greatest high end of the
// pixels' intervals, compare/PolygonOffset.hpp) and those the raster stored (its depth minus the
// exact depth of the ray's hit).
struct OffsetRecord {
  std::string object;
  double factor = 0.0, units = 0.0, clamp = 0.0;
  std::int64_t pixels = 0;
  double predictedLow = 0.0, predictedHigh = 0.0;
  double measuredMin = 0.0, measuredMax = 0.0;
  bool operator==(const OffsetRecord&) const = default;
};

// What the samples of a multisampled run say per pixel (engine/MultisampleRun): a pixel is
// unexplained where any of its samples is (coverage or ids unexplained, depth beyond tolerance).
struct MultisamplePixels {
  std::int64_t pixels = 0;
  std::int64_t covered = 0;          // some sample of the raster shows a primitive
  std::int64_t partlyCovered = 0;    // of those, some sample shows the background (an edge)
  std::int64_t mixedPrimitives = 0;  // of those covered, samples show different primitives
  std::int64_t unexplained = 0;
  bool operator==(const MultisamplePixels&) const = default;
};

// The sample a run of a multisampled frame compares: sample `index` of `count`, at `position` in
// its pixel (glGetMultisamplefv: window coordinates from the lower-left corner, in pixels), and
// the whole frame's per-pixel figures (the same on each of its sample runs).
struct SampleRecord {
  int index = 0;
  int count = 1;
  glm::dvec2 position{0.5, 0.5};
  MultisamplePixels pixels;
  bool operator==(const SampleRecord&) const = default;
};

// What the screen path (clipray reconcile --analytic screen, ScreenEvaluator.hpp) did with the
// run's frame: pixels no triangle can be hit at, decided by one watertight test, by several (the
// nearest within the depth margin), and traced by the ray path; tests that missed where the
// bounds said hit (zero unless a bound is wrong); the bound on the rays' deviation (NDC). Or, where
// it left the whole frame to the ray path, why (the counts are then zero).
struct ScreenPathRecord {
  std::int64_t background = 0;
  std::int64_t decided = 0;
  std::int64_t contested = 0;
  std::int64_t traced = 0;
  std::int64_t boundMisses = 0;
  double rayDeviationNdc = 0.0;
  // Of the decided pixels, those the compare took from their planes and those it compared along
  // their rays (RunMetrics::planePixels).
  std::int64_t comparedFromPlanes = 0;
  std::int64_t comparedAlongRays = 0;
  std::string declined;  // empty where the screen path evaluated the frame
  // The frames the counts cover: 1, or where objects are drawn in groups of their own state, one
  // per group the screen path evaluated (ScreenEvaluation::frames and groups).
  std::int64_t frames = 1;
  std::int64_t groups = 1;
  bool operator==(const ScreenPathRecord&) const = default;
};

struct RunRecord {
  std::string scene;
  std::string camera;
  DepthMode convention;
  DepthFormat depthFormat = DepthFormat::Float32;
  VertexMode vertexMode = VertexMode::World;
  Viewport size;
  glm::dvec2 depthRange{0.0, 1.0};  // glDepthRange(n, f) it was drawn with (Scene::depthRange)
  bool depthClamp = false;          // drawn with GL_DEPTH_CLAMP (Scene::depthClamp)
  std::vector<OffsetRecord> polygonOffsets{};  // the objects drawn with a polygon offset
  std::optional<SampleRecord> sample;          // set for the runs of a multisampled frame
  std::optional<ScreenPathRecord> screenPath;  // set on the screen path
  RunMetrics metrics;
  RunTimings timings;
  // The CPU time the process spent in each phase, every thread's (the GL driver's in the raster
  // pass): cpu / timings is how many cores a phase kept busy (PhaseClock).
  RunTimings cpu;
  // How many times the run was made (clipray reconcile --rounds). With more than one, timings
  // holds each timing's median over rounds 2.., analyticOverRaster the median of those rounds'
  // own ratios, cpu each CPU time's median over rounds 2.., and firstRound and firstRoundCpu the
  // first (cold) round's.
  int rounds = 1;
  double analyticOverRaster = std::numeric_limits<double>::quiet_NaN();  // set with the timings
  RunTimings firstRound;
  RunTimings firstRoundCpu;
  // The largest connected components of the unexplained pixels (kReportedClusters of them; none
  // for a consistent run).
  MismatchClusters clusters;
  // Where the app's render function drew with other state than the run says (its clip control,
  // depth range, depth test, face culling, depth clamp): one line each (engine/AppStateNotes).
  std::vector<std::string> notes;
  // The convention check of the run's camera under the run's state: an error the scene does not
  // expect fails the run (RunVerdict::ConventionError).
  std::vector<RunFinding> conventionFindings;
  // What each side hit at each of clusters.largest's pixels, in its order (or nothing, for a
  // record made without the scene at hand).
  std::vector<PixelHits> clusterHits;
  // The run's worst pixel as both sides saw it (engine::worstPixels' order: unexplained first,
  // then by error / tolerance); none where no pixel shows anything.
  std::optional<PixelHits> worstPixel;
  // The RenderDoc capture of the app's frame kept for this failing run
  // (ReconcileOptions::renderDocCaptures); empty: none.
  std::string capture;
  // Filled by encodeRunImages (the four full-size PNGs), encodeThumbnails and encodeClusterCrops.
  std::vector<EncodedImage> images;
};

// A run's verdict: inconsistent where raster and rays disagree beyond what is explained (whatever
// the check says), else convention-error where the check on its camera found an error the scene
// does not expect, else consistent.
enum class RunVerdict { Consistent, Inconsistent, ConventionError };
RunVerdict runVerdict(const RunRecord& run);
// "consistent", "inconsistent", "convention-error" (report.json, JUnit's failure type).
const char* runVerdictName(RunVerdict verdict);
// Only consistent runs pass: the others fail a reconcile (exit status 1).
inline bool runPasses(const RunRecord& run) {
  return runVerdict(run) == RunVerdict::Consistent;
}
// The errors the scene does not expect (what makes a convention-error).
std::size_t unexpectedConventionErrors(const RunRecord& run);
// The summary line's note on the run's findings: "check error:depth-convention-mismatch
// (expected), warning:y-flipped"; empty without findings.
std::string conventionNoteText(const RunRecord& run);
// Each finding on its lines after `indent`: "error [code] message (expected by the scene)" and
// "  fix: ...".
std::string conventionFindingsText(const RunRecord& run, const std::string& indent);

// How many of a run's largest unexplained clusters are reported.
inline constexpr std::size_t kReportedClusters = 5;

// The same runs made round after round (rounds[r][i]: run i of round r; clipray reconcile
// --rounds) as one record per run: the last round's (with its images), whose timings and CPU times
// are each one's median over rounds 2.. (the first round pays for cold caches, page faults and the
// GL driver's first draws), whose analyticOverRaster is the median of those rounds' own ratios,
// and whose firstRound and firstRoundCpu keep round 1's. One round is returned as it is. No rounds
// or rounds of different runs are a bug (InternalError); a round that measured a run differently
// from the last (anything but timings and images) throws std::runtime_error naming the run.
std::vector<RunRecord> mergeRounds(std::vector<std::vector<RunRecord>> rounds);

// "<scene>/<camera>-<convention>-<format>-<vertex mode>": the run's folder under the output folder;
// "-s<index>of<count>" after it for a sample of a multisampled frame.
std::string runFolderName(const RunRecord& run);
// "", or " sample <index> of <count>" (GL's sample index, from 0) for a sample of a multisampled
// frame: after the vertex mode wherever a run is named.
std::string sampleSuffix(const RunRecord& run);
// A scene or camera name as one safe path component: characters other than letters, digits and
// "._+-" become '_'; a name that is empty or only dots becomes underscores.
std::string pathComponent(const std::string& name);
// Throws InputError when two runs would share a folder: two scenes whose names are the same once
// made safe (two files called standard.json in different folders, "a b" and "a_b"), or two
// cameras of one scene ("a/b" and "a_b"). One run's images would overwrite the other's.
void checkDistinctRunFolders(const std::vector<const Scene*>& scenes);

// Encodes raster depth, ray depth, error heat map (with its colour scale drawn in) and mismatch
// mask PNGs for a run, and stores them in run.images.
void encodeRunImages(RunRecord& run, const PixelComparison& pixels);

// Where a report came from, beside the clipray version and git commit reportJson always records:
// the command line and when the command started (UTC, ISO 8601). Empty fields are left out.
struct ReportProvenance {
  std::string commandLine;
  std::string startedAt;
  // With --shard I/N: this report holds shard I of N (1-based), {index, count} in report.json.
  int shardIndex = 0, shardCount = 0;
};

nlohmann::json reportJson(const std::vector<RunRecord>& runs, const GlInfo& gl,
                          const ReportProvenance& provenance = {});
// The runs' indices, the worst first: inconsistent runs, then by unexplained pixels (coverage, id
// and depths beyond tolerance together), then by worst error / tolerance (NaN the worst); ties in
// run order.
std::vector<std::size_t> worstFirst(const std::vector<RunRecord>& runs);
// A header, one line per run, the worst first (worstFirst), then a totals line and a legend of the
// figures. Each column is as wide as its widest entry.
std::string textSummary(const std::vector<RunRecord>& runs);
// The runs' lines of a summary of them alone, in their order, in columns sized to them, without
// newlines.
std::vector<std::string> runSummaryLines(const std::vector<RunRecord>& runs);
// The run's line of a summary of it alone.
std::string runSummaryLine(const RunRecord& run);
// "<scene>/<camera> <convention> <format> <vertex mode>[ sample i of n]": a run as messages name
// it.
std::string runTitleText(const RunRecord& run);
// Which side hit what at the run's worst pixel and at its clusters' pixels, one line each, each
// line after `indent`: "worst pixel (12, 40): coverage_unexplained: raster nothing, ray ...".
std::string runHitsText(const RunRecord& run, const std::string& indent);
// The summary's depth figures of a run: "tol MAX/P99 rel P99" (error / predicted tolerance, and
// distance error / eye distance), or "depth n/a (0 compared)" where no pixel showed the same
// primitive on both sides.
std::string depthFiguresText(const RunMetrics& metrics);
// A figure as the summary line writes it: two significant digits, a short exponent ("2.1e-7",
// "1.2e5"), "nan" and "inf" spelled out.
std::string shortNumber(double value);

// Writes report.json, summary.txt, index.html and every run's PNGs under outDir (created if
// missing), each atomically.
void writeReport(const std::filesystem::path& outDir, const std::vector<RunRecord>& runs,
                 const GlInfo& gl, const ReportProvenance& provenance = {});

// Writes bytes to path atomically: a temp file in the same folder, then rename.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace clipray

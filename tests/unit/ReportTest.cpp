// report.json, the text summary and the atomic file writing (the four PNGs of a run:
// EncodeRunImagesTest.cpp).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "clipray/report/Report.hpp"
#include "clipray/util/Check.hpp"
#include "clipray/util/Version.hpp"
#include "support/ReportSamples.hpp"

namespace clipray {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::imageNamed;
using ::testing::Not;
using testing::sampleGl;
using testing::sampleRun;
using testing::tinyComparison;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A fresh, empty folder under the test temp directory.
fs::path freshFolder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() /
                          ("clipray-report-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// ---- runFolderName -----------------------------------------------------------------------------

TEST(RunFolderName, JoinsSceneCameraConventionFormatAndVertexMode) {
  RunRecord run = sampleRun();
  run.depthFormat = DepthFormat::Float32;
  EXPECT_EQ(runFolderName(run), "standard/main-zo-32f-world");
  run.convention = kZeroToOneReversed;
  run.depthFormat = DepthFormat::Unorm16;
  run.vertexMode = VertexMode::CameraRelative;
  EXPECT_EQ(runFolderName(run), "standard/main-zo-reversed-16-camera-relative");
  run.convention = kNegativeOneToOne;
  run.vertexMode = VertexMode::Pretransformed;
  EXPECT_EQ(runFolderName(run), "standard/main-no-16-pretransformed");
}

TEST(RunFolderName, NamesCannotEscapeTheOutputFolder) {
  RunRecord run = sampleRun();
  run.depthFormat = DepthFormat::Float32;
  run.scene = "..";
  run.camera = "a/b c";
  EXPECT_EQ(runFolderName(run), "__/a_b_c-zo-32f-world");
  // Assigned without string literals: "" and "." trip a GCC 12 -Wrestrict false positive here.
  run.scene.clear();
  run.camera = std::string(1, '.');
  EXPECT_EQ(runFolderName(run), "_/_-zo-32f-world");
}

// ---- report.json -------------------------------------------------------------------------------

TEST(ReportJson, WritesEveryFieldOfARun) {
  RunRecord run = sampleRun();
  run.images = {{"standard/main-zo-24-world/raster_depth.png", "x"},
                {"standard/main-zo-24-world/ray_depth.png", "x"},
                {"standard/main-zo-24-world/error_heatmap.png", "x"},
                {"standard/main-zo-24-world/mismatch.png", "x"},
                {"standard/main-zo-24-world/thumb_mismatch.png", "x"},
                {"standard/main-zo-24-world/cluster1.png", "x"}};
  // Two clusters of three; the second has no crop image.
  run.clusters.count = 3;
  run.clusters.largest = {{2, 2, 0, 0, 10, 20, 11, 20, 10, 20}, {1, 0, 0, 1, 5, 0, 5, 0, 5, 0}};
  // What each side hit at the clusters' pixels and at the worst pixel: a depth beyond tolerance
  // on a sphere at the second.
  PixelHits sphere;
  sphere.x = 5;
  sphere.y = 0;
  sphere.pixelClass = PixelClass::DepthBeyondTolerance;
  sphere.raster = {9, "ball", "sphere", -1, 0.5};
  sphere.ray = {9, "ball", "sphere", -1, 0.25};
  sphere.toleranceRatio = 2.5;
  run.clusterHits = {testing::sampleHits(10, 20), sphere};
  run.worstPixel = testing::sampleHits(10, 20);
  const nlohmann::json j = reportJson({run}, sampleGl());

  EXPECT_EQ(j["tool"], "clipray");
  EXPECT_EQ(j["format_version"], 1);
  const nlohmann::json gl = nlohmann::json::parse(R"json({"backend": "osmesa", "vendor": "Mesa",
      "renderer": "llvmpipe (LLVM 15.0.6, 256 bits)", "version": "4.5 (Core)",
      "subpixel_bits": 8})json");
  EXPECT_EQ(j["gl"], gl);
  const nlohmann::json summary = nlohmann::json::parse(
      R"({"runs": 1, "consistent": 0, "inconsistent": 1, "convention_error": 0,
          "verdict": "inconsistent"})");
  EXPECT_EQ(j["summary"], summary);
  EXPECT_EQ(j["clipray_version"], versionNumber());
  EXPECT_EQ(j["git_commit"], gitCommit());
  // tool, format_version, clipray_version, git_commit, gl, summary, runs (no provenance given)
  EXPECT_EQ(j.size(), 7u);
  const nlohmann::json withProvenance =
      reportJson({run}, sampleGl(), {"clipray reconcile a.json", "2026-11-25T05:00:00Z"});
  EXPECT_EQ(withProvenance["command_line"], "clipray reconcile a.json");
  EXPECT_EQ(withProvenance["started_at"], "2026-11-25T05:00:00Z");
  EXPECT_EQ(withProvenance.size(), 9u);
  ASSERT_EQ(j["runs"].size(), 1u);
  const nlohmann::json expected = nlohmann::json::parse(R"({
    "scene": "standard", "camera": "main", "convention": "zo", "depth_format": "24",
    "vertex_mode": "world", "size": {"width": 640, "height": 480},
    "pixels": 307200, "raster_hits": 150000, "ray_hits": 150010,
    "coverage_mismatch": {"total": 12, "edge_ambiguous": 10, "unexplained": 2},
    "id_mismatch": {"total": 3, "depth_ambiguous": 2, "edge_ambiguous": 1, "unexplained": 0},
    "depth_compared": 149990, "depth_beyond_tolerance": 0,
    "depth_error_quanta": {"max": 1.0, "p50": 0.25, "p99": 0.5},
    "distance_rel_error": {"max": 4.5e-7, "p50": 1.5e-8, "p99": 2.125e-7},
    "tolerance_ratio": {"max": 0.75, "p99": 0.5},
    "by_kind": {"sphere": {"depth_compared": 1000,
                           "depth_error_quanta": {"max": 3.0, "p50": 1.5, "p99": 2.5},
                           "distance_rel_error": {"max": 2e-5, "p50": 1e-6, "p99": 1.5e-5},
                           "tolerance_ratio": {"max": 0.25, "p99": 0.125}}},
    "verdict": "inconsistent", "convention_check": [],
    "timings_ms": {"raster": 1.5, "readback": 2.5, "rays": 3.25, "intersect": 40.0, "compare": 5.0},
    "cpu_ms": {"raster": 2.75, "readback": 2.5, "rays": 3.0, "intersect": 78.5, "compare": 9.75},
    "analytic_over_raster": 32.5,
    "images": {"raster_depth": "standard/main-zo-24-world/raster_depth.png",
               "ray_depth": "standard/main-zo-24-world/ray_depth.png",
               "error_heatmap": "standard/main-zo-24-world/error_heatmap.png",
               "mismatch": "standard/main-zo-24-world/mismatch.png"},
    "thumbnails": {"mismatch": "standard/main-zo-24-world/thumb_mismatch.png", "heatmap": null},
    "cluster_count": 3,
    "clusters": [
      {"pixels": 2, "coverage_unexplained": 2, "id_unexplained": 0, "depth_beyond_tolerance": 0,
       "pixel_gl": {"x": 10, "y": 20}, "pixel_image": {"x": 10, "y": 459},
       "bounds_gl": {"x_min": 10, "y_min": 20, "x_max": 11, "y_max": 20},
       "bounds_image": {"x_min": 10, "y_min": 459, "x_max": 11, "y_max": 459},
       "crop": "standard/main-zo-24-world/cluster1.png",
       "class": "coverage_unexplained", "raster": null,
       "ray": {"id": 4, "object": "far_wall", "kind": "triangle", "triangle": 1, "depth": 0.75},
       "tolerance_ratio": null},
      {"pixels": 1, "coverage_unexplained": 0, "id_unexplained": 0, "depth_beyond_tolerance": 1,
       "pixel_gl": {"x": 5, "y": 0}, "pixel_image": {"x": 5, "y": 479},
       "bounds_gl": {"x_min": 5, "y_min": 0, "x_max": 5, "y_max": 0},
       "bounds_image": {"x_min": 5, "y_min": 479, "x_max": 5, "y_max": 479},
       "crop": null,
       "class": "depth_beyond_tolerance",
       "raster": {"id": 9, "object": "ball", "kind": "sphere", "triangle": null, "depth": 0.5},
       "ray": {"id": 9, "object": "ball", "kind": "sphere", "triangle": null, "depth": 0.25},
       "tolerance_ratio": 2.5}
    ],
    "worst_pixel": {
      "pixel_gl": {"x": 10, "y": 20}, "pixel_image": {"x": 10, "y": 459},
      "class": "coverage_unexplained", "raster": null,
      "ray": {"id": 4, "object": "far_wall", "kind": "triangle", "triangle": 1, "depth": 0.75},
      "tolerance_ratio": null}
  })");
  EXPECT_EQ(j["runs"][0], expected) << j["runs"][0].dump(2);
}

TEST(ReportJson, ARunMadeInRoundsAlsoGivesItsFirstRound) {
  RunRecord run = sampleRun();
  run.rounds = 5;
  run.firstRound = {80.0, 12.5, 0.25, 160.0, 96.0};
  run.firstRoundCpu = {120.0, 12.25, 0.5, 310.0, 180.0};
  const nlohmann::json r = reportJson({run}, sampleGl())["runs"][0];
  EXPECT_EQ(r["rounds"], 5);
  EXPECT_EQ(r["first_round_timings_ms"],
            nlohmann::json::parse(R"({"raster": 80.0, "readback": 12.5, "rays": 0.25,
                                      "intersect": 160.0, "compare": 96.0})"));
  EXPECT_EQ(r["first_round_cpu_ms"],
            nlohmann::json::parse(R"({"raster": 120.0, "readback": 12.25, "rays": 0.5,
                                      "intersect": 310.0, "compare": 180.0})"));
  EXPECT_EQ(r["cpu_ms"]["intersect"], 78.5);
  EXPECT_EQ(r["timings_ms"]["intersect"], 40.0);
  EXPECT_EQ(r["analytic_over_raster"], 32.5);
  // One round: neither key (the run's timings are that round's).
  const nlohmann::json once = reportJson({sampleRun()}, sampleGl())["runs"][0];
  EXPECT_FALSE(once.contains("rounds"));
  EXPECT_FALSE(once.contains("first_round_timings_ms"));
  EXPECT_FALSE(once.contains("first_round_cpu_ms"));
}

// Run i of a round whose timings are t and CPU times cpu (and analyticOverRaster their own ratio),
// named by i.
RunRecord roundRun(int i, RunTimings t, RunTimings cpu = {}) {
  RunRecord run = sampleRun();
  run.camera = "camera" + std::to_string(i);
  run.timings = t;
  run.cpu = cpu;
  run.analyticOverRaster = t.analyticOverRaster();
  return run;
}

TEST(MergeRounds, EachTimingIsItsMedianOverRoundsTwoOnAndTheRatioTheMedianOfRatios) {
  // Run 0: round 1 is cold; rounds 2 and 3 give ratios (1 + 6 + 3) / 10 = 1 and (1 + 10 + 10) /
  // 14 = 1.5, so 1.25, where the ratio of the medians would be (1 + 8 + 6.5) / 12 = 1.2917.
  // Run 1: rounds 2 and 3 give (8 + 6) / 2 = 7 and ratios 7/8 and 7/6.
  // Run 0's CPU times: medians of rounds 2 and 3 apart from the wall times'.
  std::vector<std::vector<RunRecord>> rounds = {
      {roundRun(0, {100, 20, 2, 90, 70}, {200, 21, 3, 170, 130}), roundRun(1, {50, 5, 1, 40, 30})},
      {roundRun(0, {10, 2, 1, 6, 3}, {19, 3, 1, 11, 5}), roundRun(1, {8, 1, 1, 4, 2})},
      {roundRun(0, {14, 4, 1, 10, 10}, {27, 5, 2, 21, 19}), roundRun(1, {6, 3, 1, 5, 1})},
  };
  rounds[2][0].images = {{"standard/camera0-zo-24-world/mismatch.png", "last"}};
  for (auto& round : rounds) round[1].metrics.depthCompared = 7;  // what every round measured
  std::vector<std::vector<RunRecord>> fourRounds = rounds;
  fourRounds.push_back({roundRun(0, {12, 3, 1, 8, 5}), roundRun(1, {7, 2, 1, 3, 3})});
  fourRounds[3][1].metrics.depthCompared = 7;

  const std::vector<RunRecord> merged = mergeRounds(rounds);
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_EQ(merged[0].rounds, 3);
  EXPECT_EQ(merged[0].timings.raster, 12.0);
  EXPECT_EQ(merged[0].timings.readback, 3.0);
  EXPECT_EQ(merged[0].timings.rays, 1.0);
  EXPECT_EQ(merged[0].timings.intersect, 8.0);
  EXPECT_EQ(merged[0].timings.compare, 6.5);
  EXPECT_EQ(merged[0].analyticOverRaster, 1.25);
  EXPECT_EQ(merged[0].firstRound.raster, 100.0);
  EXPECT_EQ(merged[0].firstRound.compare, 70.0);
  EXPECT_EQ(merged[0].cpu.raster, 23.0);
  EXPECT_EQ(merged[0].cpu.readback, 4.0);
  EXPECT_EQ(merged[0].cpu.rays, 1.5);
  EXPECT_EQ(merged[0].cpu.intersect, 16.0);
  EXPECT_EQ(merged[0].cpu.compare, 12.0);
  EXPECT_EQ(merged[0].firstRoundCpu.raster, 200.0);
  EXPECT_EQ(merged[0].firstRoundCpu.intersect, 170.0);
  // The last round's record: its images and metrics.
  ASSERT_EQ(merged[0].images.size(), 1u);
  EXPECT_EQ(merged[0].images[0].pngBytes, "last");
  EXPECT_EQ(merged[1].metrics.depthCompared, 7);
  EXPECT_EQ(merged[1].timings.raster, 7.0);
  EXPECT_EQ(merged[1].timings.intersect, 4.5);
  EXPECT_EQ(merged[1].timings.compare, 1.5);
  EXPECT_EQ(merged[1].analyticOverRaster, 0.5 * (7.0 / 8.0 + 7.0 / 6.0));

  // Rounds 2, 3 and 4 of run 1: rasters (8, 6, 7) -> 7; ratios 7/8, 7/6, 7/7 -> 1.
  const std::vector<RunRecord> mergedFour = mergeRounds(fourRounds);
  EXPECT_EQ(mergedFour[1].rounds, 4);
  EXPECT_EQ(mergedFour[1].timings.raster, 7.0);
  EXPECT_EQ(mergedFour[1].timings.intersect, 4.0);
  EXPECT_EQ(mergedFour[1].timings.compare, 2.0);
  EXPECT_EQ(mergedFour[1].analyticOverRaster, 1.0);
  EXPECT_EQ(mergedFour[1].firstRound.raster, 50.0);
}

TEST(MergeRounds, OneRoundIsReturnedAsItIs) {
  const std::vector<RunRecord> merged = mergeRounds({{roundRun(0, {10, 2, 1, 6, 3})}});
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_EQ(merged[0].rounds, 1);
  EXPECT_EQ(merged[0].timings.intersect, 6.0);
  EXPECT_EQ(merged[0].analyticOverRaster, 1.0);
}

TEST(MergeRounds, ClustersAreMeasuredTheirCropsAndThumbnailsAreImages) {
  // Images (crops and thumbnails too) come from the last round only: not a difference.
  std::vector<std::vector<RunRecord>> rounds = {{roundRun(0, {10, 2, 1, 6, 3})},
                                                {roundRun(0, {10, 2, 1, 6, 3})}};
  for (auto& round : rounds) {
    round[0].clusters.count = 1;
    round[0].clusters.largest = {{2, 2, 0, 0, 1, 1, 2, 1, 1, 1}};
  }
  rounds[1][0].images = {{"standard/camera0-zo-24-world/cluster1.png", "crop"},
                         {"standard/camera0-zo-24-world/thumb_mismatch.png", "thumb"}};
  const std::vector<RunRecord> merged = mergeRounds(rounds);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_EQ(merged[0].images.size(), 2u);
  EXPECT_EQ(merged[0].clusters.largest.size(), 1u);
  // A cluster found elsewhere is a different measurement.
  rounds[0][0].clusters.largest[0].x = 2;
  EXPECT_THROW(mergeRounds(rounds), std::runtime_error);
}

TEST(MergeRounds, ARoundThatMeasuredARunDifferentlyIsReported) {
  std::vector<std::vector<RunRecord>> rounds = {{roundRun(0, {10, 2, 1, 6, 3})},
                                                {roundRun(0, {10, 2, 1, 6, 3})},
                                                {roundRun(0, {10, 2, 1, 6, 3})}};
  rounds[1][0].metrics.toleranceRatio.p99 = 0.5000001;
  try {
    mergeRounds(rounds);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(),
                 "standard/camera0-zo-24-world: round 2 measured it differently from round 3 (a "
                 "nondeterministic renderer or a clipray bug)");
  }
}

TEST(MergeRounds, ATimingThatIsNaNInARoundMakesItsMedianNaN) {
  RunTimings bad{10, 2, 1, 6, 3};
  bad.compare = std::numeric_limits<double>::quiet_NaN();
  const std::vector<RunRecord> merged = mergeRounds({{roundRun(0, {10, 2, 1, 6, 3})},
                                                     {roundRun(0, {10, 2, 1, 6, 3})},
                                                     {roundRun(0, bad)},
                                                     {roundRun(0, {12, 2, 1, 6, 3})}});
  EXPECT_TRUE(std::isnan(merged[0].timings.compare));
  EXPECT_TRUE(std::isnan(merged[0].analyticOverRaster));
  EXPECT_EQ(merged[0].timings.raster, 10.0);
}

TEST(MergeRounds, RoundsOfDifferentRunsAreRefused) {
  EXPECT_THROW(mergeRounds({}), InternalError);
  EXPECT_THROW(mergeRounds({{roundRun(0, {})}, {roundRun(1, {})}}), InternalError);
  EXPECT_THROW(mergeRounds({{roundRun(0, {})}, {roundRun(0, {}), roundRun(1, {})}}), InternalError);
}

TEST(ReportJson, ConsistentRunsAndAnEmptyReport) {
  RunRecord run = sampleRun();
  run.metrics.coverageMismatch.unexplained = 0;
  const nlohmann::json j = reportJson({run, run}, sampleGl());
  EXPECT_EQ(j["summary"]["runs"], 2);
  EXPECT_EQ(j["summary"]["consistent"], 2);
  EXPECT_EQ(j["summary"]["inconsistent"], 0);
  EXPECT_EQ(j["summary"]["verdict"], "consistent");
  EXPECT_EQ(j["runs"][1]["verdict"], "consistent");
  // Images not encoded yet: the keys are there, the paths are null.
  EXPECT_TRUE(j["runs"][0]["images"]["mismatch"].is_null());

  const nlohmann::json empty = reportJson({}, sampleGl());
  EXPECT_EQ(empty["summary"]["runs"], 0);
  EXPECT_TRUE(empty["runs"].is_array());
  EXPECT_TRUE(empty["runs"].empty());
}

TEST(ReportJson, NonFiniteNumbersBecomeNull) {
  RunRecord run = sampleRun();
  run.metrics.depthErrorQuanta = {kNaN, kInf, -kInf};
  run.metrics.toleranceRatio.max = kNaN;
  run.timings.rays = kNaN;
  const nlohmann::json j = reportJson({run}, sampleGl());
  const nlohmann::json& r = j["runs"][0];
  EXPECT_TRUE(r["depth_error_quanta"]["max"].is_null());
  EXPECT_TRUE(r["depth_error_quanta"]["p50"].is_null());
  EXPECT_TRUE(r["depth_error_quanta"]["p99"].is_null());
  EXPECT_TRUE(r["tolerance_ratio"]["max"].is_null());
  EXPECT_EQ(r["tolerance_ratio"]["p99"], 0.5);
  EXPECT_TRUE(r["timings_ms"]["rays"].is_null());
  // And the text is valid JSON that reads back the same.
  const std::string text = j.dump(2);
  EXPECT_THAT(text, Not(HasSubstr("nan")));
  EXPECT_THAT(text, Not(HasSubstr("inf")));
  EXPECT_EQ(nlohmann::json::parse(text), j);
}

// ---- text summary ------------------------------------------------------------------------------

TEST(TextSummary, WorstRunsFirstThenTotals) {
  RunRecord ok = sampleRun();
  ok.camera = "ok";
  ok.metrics.coverageMismatch.unexplained = 0;
  ok.metrics.toleranceRatio.max = 0.9;  // the highest ratio, but consistent: still last

  RunRecord one = sampleRun();  // 1 unexplained, ratio max 0.5
  one.camera = "one";
  one.metrics.coverageMismatch.unexplained = 1;
  one.metrics.toleranceRatio.max = 0.5;

  RunRecord oneWorse = one;  // 1 unexplained, ratio max 0.8
  oneWorse.camera = "oneworse";
  oneWorse.metrics.coverageMismatch.unexplained = 0;
  oneWorse.metrics.depthBeyondTolerance = 1;
  oneWorse.metrics.toleranceRatio.max = 0.8;

  RunRecord five = sampleRun();  // 2 + 1 + 2 = 5 unexplained
  five.camera = "five";
  five.metrics.coverageMismatch.unexplained = 2;
  five.metrics.idMismatch.unexplained = 1;
  five.metrics.depthBeyondTolerance = 2;
  five.metrics.toleranceRatio.max = 0.1;

  const std::vector<std::string> got = lines(textSummary({ok, one, five, oneWorse}));
  ASSERT_EQ(got.size(), 10u);  // header, 4 runs, totals, 4 legend lines
  EXPECT_THAT(got[0], ::testing::StartsWith("verdict      scene/camera "));
  EXPECT_THAT(got[1], ::testing::StartsWith("INCONSISTENT standard/five "));
  EXPECT_THAT(got[2], ::testing::StartsWith("INCONSISTENT standard/oneworse "));
  EXPECT_THAT(got[3], ::testing::StartsWith("INCONSISTENT standard/one "));
  EXPECT_THAT(got[4], ::testing::StartsWith("consistent   standard/ok "));
  EXPECT_EQ(got[5], "4 runs: 1 consistent, 3 inconsistent");
  for (const std::string& line : got) EXPECT_LT(line.size(), 160u) << line;
}

TEST(TextSummary, ColumnsSizedToTheirContent) {
  RunRecord run = sampleRun();
  EXPECT_EQ(textSummary({run}),
            // A header over the columns: verdict, scene/camera, convention, format, vertex mode,
            // size, then the figures, explained after the totals. Each column as wide as its
            // widest entry, header included.
            "verdict      scene/camera  convention fmt vertex mode size    "
            "mismatches and depth error\n"
            "INCONSISTENT standard/main zo         24  world       640x480 "
            "cov 12 (e10 u2) id 3 (z2 e1 u0) >tol 0 tol 0.75/0.5 rel 2.1e-7\n"
            "1 runs: 0 consistent, 1 inconsistent\n"
            "  cov: coverage mismatches (e edge-ambiguous, u unexplained); >tol: depths beyond "
            "tolerance\n"
            "  id: id mismatches (z depth-ambiguous, e edge-ambiguous, u unexplained)\n"
            "  tol: depth error / predicted tolerance, max/p99 (above 1: beyond it); rel: p99 "
            "distance error / eye distance\n"
            "  n/a (0 compared): no pixel where both sides hit the same primitive\n");
  // Columns line up whatever the names' lengths: the widest entry sets each column.
  RunRecord other = run;
  other.camera = "a_camera_with_a_long_name";
  other.convention = *DepthMode::parse("zo-reversed-upper-left");
  other.depthFormat = DepthFormat::Float32;
  other.vertexMode = VertexMode::CameraRelative;
  other.size = {7, 3};
  other.metrics.toleranceRatio.max = kNaN;
  other.metrics.coverageMismatch = {1234, 1000, 234};
  const std::vector<std::string> got = lines(textSummary({run, other}));
  ASSERT_EQ(got.size(), 8u);
  EXPECT_EQ(got[1],
            "INCONSISTENT standard/a_camera_with_a_long_name zo-reversed-upper-left 32f "
            "camera-relative 7x3     cov 1234 (e1000 u234) id 3 (z2 e1 u0) >tol 0 tol nan/0.5 "
            "rel 2.1e-7");  // NaN sorts as the worst ratio
  EXPECT_EQ(got[2],
            "INCONSISTENT standard/main                      zo                     24  "
            "world           640x480 cov 12 (e10 u2)       id 3 (z2 e1 u0) >tol 0 tol 0.75/0.5 "
            "rel 2.1e-7");
  EXPECT_EQ(got[0].find(" mismatches "), got[1].find(" cov "));  // the header over the columns
  EXPECT_EQ(got[0].find(" size "), got[1].find(" 7x3 "));
  for (const char* column : {" cov ", " id ", " >tol ", " tol "}) {
    EXPECT_EQ(got[1].find(column), got[2].find(column)) << column;
  }
}

TEST(TextSummary, DepthFiguresAreNotAvailableWhereNothingWasCompared) {
  RunRecord run = sampleRun();
  run.metrics.depthCompared = 0;
  run.metrics.depthErrorQuanta = {};
  run.metrics.distanceRelError = {};
  run.metrics.toleranceRatio = {};
  EXPECT_THAT(runSummaryLine(run), ::testing::EndsWith(" >tol 0 depth n/a (0 compared)"));
  EXPECT_EQ(depthFiguresText(run.metrics), "depth n/a (0 compared)");
  EXPECT_EQ(depthFiguresText(sampleRun().metrics), "tol 0.75/0.5 rel 2.1e-7");
}

TEST(TextSummary, RunSummaryLinesShareTheirColumns) {
  RunRecord a = sampleRun();
  RunRecord b = sampleRun();
  b.camera = "a_longer_camera";
  const std::vector<std::string> both = runSummaryLines({a, b});
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[0].find(" cov "), both[1].find(" cov "));
  EXPECT_THAT(both[0], ::testing::StartsWith("INCONSISTENT standard/main            zo "));
  // One run alone: columns as wide as it needs.
  EXPECT_THAT(runSummaryLine(a), ::testing::StartsWith("INCONSISTENT standard/main zo "));
}

TEST(TextSummary, SaysWhichSideHitWhatInTheInconsistentRuns) {
  RunRecord bad = sampleRun();
  bad.clusters.count = 1;
  bad.clusters.largest = {{2, 2, 0, 0, 10, 20, 11, 20, 10, 20}};
  bad.clusterHits = {testing::sampleHits(10, 20)};
  PixelHits worst = testing::sampleHits(11, 20);
  worst.pixelClass = PixelClass::IdUnexplained;
  worst.raster = {2, "floor", "triangle", 0, 0.5};
  bad.worstPixel = worst;
  RunRecord good = sampleRun();  // consistent: its worst pixel is not shown
  good.camera = "good";
  good.metrics.coverageMismatch.unexplained = 0;
  good.worstPixel = worst;
  const std::vector<std::string> got = lines(textSummary({good, bad}));
  ASSERT_EQ(got.size(), 12u);  // header, 2 runs, totals, 4 lines of hits, 4 legend lines
  EXPECT_EQ(got[3], "2 runs: 1 consistent, 1 inconsistent");
  EXPECT_EQ(got[4],
            "which side hit what in the inconsistent runs (pixels in GL window coordinates, y up "
            "from the bottom row):");
  EXPECT_EQ(got[5], "  standard/main zo 24 world");
  EXPECT_EQ(got[6],
            "    worst pixel (11, 20): id_unexplained: raster \"floor\" triangle 0 at depth 0.5, "
            "ray \"far_wall\" triangle 1 at depth 0.75");
  EXPECT_EQ(got[7],
            "    cluster 1 (2 px) at (10, 20): coverage_unexplained: raster nothing, ray "
            "\"far_wall\" triangle 1 at depth 0.75");
  EXPECT_THAT(got[8], ::testing::StartsWith("  cov: "));
}

TEST(PixelHits, NameWhatEachSideHit) {
  SurfaceHit nothing;
  EXPECT_EQ(nothing.text(), "nothing");
  EXPECT_EQ(SurfaceHit({7, "floor", "triangle", 12, 0.4998712}).text(),
            "\"floor\" triangle 12 at depth 0.499871");
  EXPECT_EQ(SurfaceHit({9, "ball", "sphere", -1, kNaN}).text(), "\"ball\" (sphere)");
  EXPECT_EQ(SurfaceHit({99, "", "unknown", -1, 0.5}).name(), "id 99");
  PixelHits hits = testing::sampleHits(1, 2);
  hits.pixelClass = PixelClass::DepthBeyondTolerance;
  hits.raster = {4, "far_wall", "triangle", 1, 0.5};
  hits.toleranceRatio = 3.25;
  EXPECT_EQ(hits.text(),
            "depth_beyond_tolerance: raster \"far_wall\" triangle 1 at depth 0.5, ray "
            "\"far_wall\" triangle 1 at depth 0.75, error/tolerance 3.2");
}

TEST(TextSummary, NoRuns) {
  EXPECT_EQ(textSummary({}), "0 runs: 0 consistent, 0 inconsistent\n");
}

// ---- files -------------------------------------------------------------------------------------

std::vector<std::string> filesUnder(const fs::path& folder) {
  std::vector<std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) out.push_back(fs::relative(entry.path(), folder).generic_string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(WriteReport, WritesImagesSummaryAndReportWithoutTempFiles) {
  const fs::path root = freshFolder("write");
  const fs::path out = root / "nested" / "out";
  RunRecord a = sampleRun();
  encodeRunImages(a, tinyComparison());
  RunRecord b = sampleRun();
  b.camera = "top";
  b.convention = kZeroToOneReversed;
  b.depthFormat = DepthFormat::Float32;
  b.metrics.coverageMismatch.unexplained = 0;
  encodeRunImages(b, tinyComparison());

  writeReport(out, {a, b}, sampleGl());
  const std::vector<std::string> expected = {
      "index.html",
      "report.json",
      "standard/main-zo-24-world/error_heatmap.png",
      "standard/main-zo-24-world/mismatch.png",
      "standard/main-zo-24-world/raster_depth.png",
      "standard/main-zo-24-world/ray_depth.png",
      "standard/top-zo-reversed-32f-world/error_heatmap.png",
      "standard/top-zo-reversed-32f-world/mismatch.png",
      "standard/top-zo-reversed-32f-world/raster_depth.png",
      "standard/top-zo-reversed-32f-world/ray_depth.png",
      "summary.txt",
  };
  EXPECT_EQ(filesUnder(out), expected);  // and so no *.tmp-* files

  const nlohmann::json report = nlohmann::json::parse(readFile(out / "report.json"));
  EXPECT_EQ(report, reportJson({a, b}, sampleGl()));
  for (const auto& run : report["runs"])
    for (const auto& [name, path] : run["images"].items())
      EXPECT_TRUE(fs::is_regular_file(out / path.get<std::string>())) << name;
  EXPECT_EQ(readFile(out / "standard/main-zo-24-world/mismatch.png"),
            imageNamed(a, "mismatch.png").pngBytes);
  EXPECT_EQ(readFile(out / "summary.txt"), textSummary({a, b}));

  // Writing again over the same folder replaces the files.
  writeReport(out, {a}, sampleGl());
  EXPECT_EQ(nlohmann::json::parse(readFile(out / "report.json"))["summary"]["runs"], 1);
  EXPECT_EQ(filesUnder(out), expected);
  fs::remove_all(root);
}

TEST(WriteReport, UnwritableOutputFolderThrowsNamingIt) {
  const fs::path root = freshFolder("blocked");
  {
    std::ofstream file(root / "file");
    file << "x";
  }
  const fs::path out = root / "file" / "out";  // a regular file stands in the way
  try {
    writeReport(out, {sampleRun()}, sampleGl());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr((root / "file").string()));
  }
  fs::remove_all(root);
}

TEST(WriteFileAtomically, WritesAndReplaces) {
  const fs::path root = freshFolder("atomic");
  const fs::path path = root / "data.bin";
  const std::string bytes("a\0b\nc", 5);
  writeFileAtomically(path, bytes);
  EXPECT_EQ(readFile(path), bytes);
  writeFileAtomically(path, "second");
  EXPECT_EQ(readFile(path), "second");
  writeFileAtomically(root / "empty", "");
  EXPECT_TRUE(fs::is_regular_file(root / "empty"));
  EXPECT_EQ(fs::file_size(root / "empty"), 0u);
  EXPECT_EQ(filesUnder(root), (std::vector<std::string>{"data.bin", "empty"}));
  fs::remove_all(root);
}

TEST(WriteFileAtomically, MissingFolderThrowsAndLeavesNothing) {
  const fs::path root = freshFolder("missing");
  const fs::path path = root / "nope" / "report.json";
  try {
    writeFileAtomically(path, "{}");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
    EXPECT_THAT(e.what(), HasSubstr("No such file or directory"));
  }
  EXPECT_FALSE(fs::exists(root / "nope"));
  EXPECT_TRUE(fs::is_empty(root));
  fs::remove_all(root);
}

TEST(WriteFileAtomically, FailedRenameRemovesTheTempFile) {
  const fs::path root = freshFolder("rename");
  fs::create_directories(root / "target" / "inside");  // a non-empty folder cannot be replaced
  EXPECT_THROW(writeFileAtomically(root / "target", "x"), std::runtime_error);
  EXPECT_EQ(filesUnder(root), std::vector<std::string>{});
  EXPECT_TRUE(fs::is_directory(root / "target" / "inside"));
  fs::remove_all(root);
}

}  // namespace
}  // namespace clipray

// report.json read back (ReportReading.hpp): what each side hit at the worst pixel and at the
// clusters' pixels comes back as written, and a report written before those fields reads as
// having none. (The whole read and merge: tests/cli/ReportMergeCliTest.cpp.)

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/report/ReportReading.hpp"
#include "support/ReportSamples.hpp"

namespace clipray {
namespace {

RunRecord runWithHits() {
  RunRecord run = testing::sampleRun();
  run.clusters.count = 2;
  run.clusters.largest = {{2, 2, 0, 0, 10, 20, 11, 20, 10, 20}, {1, 0, 0, 1, 5, 0, 5, 0, 5, 0}};
  PixelHits sphere;
  sphere.x = 5;
  sphere.pixelClass = PixelClass::DepthBeyondTolerance;
  sphere.raster = {9, "ball", "sphere", -1, 0.5};
  sphere.ray = {9, "ball", "sphere", -1, 0.25};
  sphere.toleranceRatio = 2.5;
  run.clusterHits = {testing::sampleHits(10, 20), sphere};
  run.worstPixel = testing::sampleHits(10, 20);
  return run;
}

void expectSameHits(const PixelHits& a, const PixelHits& b) {
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.pixelClass, b.pixelClass);
  EXPECT_EQ(a.raster.text(), b.raster.text());
  EXPECT_EQ(a.ray.text(), b.ray.text());
  EXPECT_EQ(a.raster.id, b.raster.id);
  EXPECT_EQ(a.ray.triangle, b.ray.triangle);
  EXPECT_EQ(std::isnan(a.toleranceRatio), std::isnan(b.toleranceRatio));
  if (!std::isnan(a.toleranceRatio)) {
    EXPECT_EQ(a.toleranceRatio, b.toleranceRatio);
  }
}

TEST(ReportReading, WhichSideHitWhatReadsBackAsWritten) {
  const RunRecord run = runWithHits();
  const std::string text = reportJson({run}, testing::sampleGl()).dump(2);
  const ReadReport read = parseReport(text, ".", "report.json");
  ASSERT_EQ(read.runs.size(), 1u);
  const RunRecord& back = read.runs[0];
  ASSERT_TRUE(back.worstPixel.has_value());
  expectSameHits(*back.worstPixel, *run.worstPixel);
  ASSERT_EQ(back.clusterHits.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) expectSameHits(back.clusterHits[k], run.clusterHits[k]);
  // And it writes the same report again.
  EXPECT_EQ(reportJson(read.runs, read.gl).dump(2), text);
}

TEST(ReportReading, AReportWithoutHitsReadsAsHavingNone) {
  nlohmann::json report = reportJson({runWithHits()}, testing::sampleGl());
  nlohmann::json& run = report["runs"][0];
  run.erase("worst_pixel");
  for (nlohmann::json& cluster : run["clusters"]) {
    for (const char* key : {"class", "raster", "ray", "tolerance_ratio"}) cluster.erase(key);
  }
  const ReadReport read = parseReport(report.dump(), ".", "report.json");
  EXPECT_FALSE(read.runs[0].worstPixel.has_value());
  EXPECT_TRUE(read.runs[0].clusterHits.empty());
  EXPECT_EQ(read.runs[0].clusters.largest.size(), 2u);
}

TEST(ReportReading, AHitThatIsNotOneIsRefusedNamingWhere) {
  nlohmann::json report = reportJson({runWithHits()}, testing::sampleGl());
  report["runs"][0]["worst_pixel"]["class"] = "purple";
  try {
    parseReport(report.dump(), ".", "r/report.json");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "r/report.json: /runs/0/worst_pixel/class: expected a pixel class (e.g. "
              "coverage_unexplained), got \"purple\"");
  }
  report = reportJson({runWithHits()}, testing::sampleGl());
  report["runs"][0]["clusters"][1]["ray"]["id"] = 0;
  EXPECT_THROW(parseReport(report.dump(), ".", "r/report.json"), InputError);
  report = reportJson({runWithHits()}, testing::sampleGl());
  report["runs"][0]["clusters"][1].erase("class");
  EXPECT_THROW(parseReport(report.dump(), ".", "r/report.json"), InputError);
}

}  // namespace
}  // namespace clipray

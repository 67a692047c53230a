// clipray report merge: the shards of a reconcile merged back are the unsharded report (every
// field but the timings, the images byte for byte, the summary's lines), and reports that do not
// belong together are refused, naming both.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::readText;
using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;

// A report's runs without what differs from one run to the next (timings), in a stable order.
std::vector<nlohmann::json> comparableRuns(const nlohmann::json& report) {
  std::vector<nlohmann::json> runs;
  for (nlohmann::json run : report["runs"]) {
    for (const char* key : {"timings_ms", "cpu_ms", "analytic_over_raster"}) run.erase(key);
    runs.push_back(std::move(run));
  }
  std::sort(runs.begin(), runs.end(),
            [](const nlohmann::json& a, const nlohmann::json& b) { return a.dump() < b.dump(); });
  return runs;
}

std::multiset<std::string> lines(const std::string& text) {
  std::multiset<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    out.insert(text.substr(start, end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

class ReportMerge : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new TempFolder;
    std::string scenes;
    // Consistent and inconsistent runs (water_reflection under zo-reversed), with images.
    for (const char* name : {"standard", "coplanar", "water_reflection", "nested_spheres",
                             "box_edge_on", "grazing_floor"}) {
      scenes += " '" + kSource + "/scenes/" + name + ".json'";
    }
    const std::string common =
        "reconcile" + scenes + " --size 48x32 --conventions zo,zo-reversed --depth-formats 32f ";
    const auto whole = runClipray(common + "--out whole --junit whole.xml", path());
    ASSERT_EQ(whole.status, 1) << whole.err;
    for (int shard = 1; shard <= 3; ++shard) {
      const auto result = runClipray(
          common + "--shard " + std::to_string(shard) + "/3 --out s" + std::to_string(shard),
          path());
      ASSERT_LE(result.status, 1) << result.err;
    }
  }
  static void TearDownTestSuite() { delete folder_; }
  static const std::filesystem::path& path() { return folder_->path(); }

 private:
  static inline TempFolder* folder_ = nullptr;
};

TEST_F(ReportMerge, TheShardsMergedBackAreTheUnshardedReport) {
  const auto merged = runClipray("report merge s3 s1 s2 --out merged --junit merged.xml", path());
  ASSERT_EQ(merged.status, 1) << merged.err;  // water_reflection under zo-reversed
  const auto whole = nlohmann::json::parse(readText(path() / "whole/report.json"));
  const auto report = nlohmann::json::parse(readText(path() / "merged/report.json"));
  EXPECT_EQ(report["runs"].size(), 14u);  // 7 scene/camera pairs x 2 conventions
  EXPECT_EQ(comparableRuns(report), comparableRuns(whole));
  EXPECT_EQ(report["summary"], whole["summary"]);
  EXPECT_FALSE(report.contains("shard"));
  EXPECT_NE(report["command_line"].get<std::string>().find(" report merge s3 s1 s2 --out merged"),
            std::string::npos);
  // Every image the merged report names is the unsharded run's, byte for byte.
  int images = 0;
  for (const auto& run : report["runs"]) {
    for (const auto& [name, image] : run["images"].items()) {
      if (image.is_null()) continue;
      ++images;
      EXPECT_EQ(readText(path() / "merged" / image.get<std::string>()),
                readText(path() / "whole" / image.get<std::string>()))
          << image;
    }
  }
  EXPECT_GE(images, 4);
  // The summary's lines are the same (their order is the worst first, ties in run order).
  EXPECT_EQ(lines(readText(path() / "merged/summary.txt")),
            lines(readText(path() / "whole/summary.txt")));
  EXPECT_TRUE(std::filesystem::is_regular_file(path() / "merged/index.html"));
  EXPECT_EQ(readText(path() / "merged.xml").find("<testsuites"),
            readText(path() / "whole.xml").find("<testsuites"));
  EXPECT_NE(merged.out.find("\nreport: merged/index.html (report.json beside it; merged from 3 "
                            "reports)\n"),
            std::string::npos)
      << merged.out;
}

TEST_F(ReportMerge, ReportsThatDoNotBelongTogetherAreRefused) {
  const auto missing = runClipray("report merge s1 s3 --out m1", path());
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(missing.err,
            "clipray: report merge: shards 2 of 3 are missing (a merge of a split takes all of "
            "its shards)\n");
  EXPECT_FALSE(std::filesystem::exists(path() / "m1"));

  const auto twice = runClipray("report merge s1 s2 s3 s2 --out m2", path());
  EXPECT_EQ(twice.status, 2);
  EXPECT_EQ(twice.err, "clipray: s2/report.json and s2/report.json: both hold shard 2/3\n");

  const auto mixed = runClipray("report merge whole s1 --out m3", path());
  EXPECT_EQ(mixed.status, 2);
  EXPECT_EQ(mixed.err,
            "clipray: s1/report.json: holds shard 1/3, but whole/report.json holds no shard: "
            "shards of one split have the same count\n");

  std::filesystem::copy(path() / "s2", path() / "s2-other",
                        std::filesystem::copy_options::recursive);
  auto report = nlohmann::json::parse(readText(path() / "s2-other/report.json"));
  report["git_commit"] = "0123456789ab";
  std::ofstream(path() / "s2-other/report.json") << report.dump(2);
  const auto build = runClipray("report merge s1 s2-other s3 --out m4", path());
  EXPECT_EQ(build.status, 2);
  EXPECT_EQ(build.err.substr(0, 50), "clipray: s2-other/report.json: git commit \"0123456");
  EXPECT_NE(build.err.find("reports of different clipray builds are not merged"),
            std::string::npos);

  const auto notReport = runClipray("report merge nowhere --out m5", path());
  EXPECT_EQ(notReport.status, 2);
  EXPECT_EQ(notReport.err, "clipray: nowhere: not a report folder (no such folder)\n");

  const auto intoInput = runClipray("report merge s1 s2 s3 --out s2", path());
  EXPECT_EQ(intoInput.status, 2);
  EXPECT_EQ(intoInput.err,
            "clipray: --out s2: is one of the reports merged (s2); merge into another folder\n");

  std::filesystem::create_directory(path() / "empty");
  const auto empty = runClipray("report merge empty --out m6", path());
  EXPECT_EQ(empty.status, 2);
  EXPECT_EQ(empty.err, "clipray: empty/report.json: cannot open file\n");
}

}  // namespace
}  // namespace clipray

// --shard I/N: the shards of a suite split its scene/camera pairs between them, each exactly once,
// by their names alone; bad shard values are refused.

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::readText;
using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;

using Pairs = std::multiset<std::pair<std::string, std::string>>;

Pairs pairsOf(const nlohmann::json& report) {
  Pairs pairs;
  for (const auto& run : report["runs"]) {
    pairs.emplace(run["scene"].get<std::string>(), run["camera"].get<std::string>());
  }
  return pairs;
}

TEST(Shards, SplitTheSceneCameraPairsOfASuiteEachExactlyOnce) {
  TempFolder folder;
  std::string scenes;
  for (const char* name : {"standard", "coplanar", "water_reflection", "nested_spheres",
                           "reversed_z", "infinite_far", "box_edge_on", "grazing_floor"}) {
    scenes += " '" + kSource + "/scenes/" + name + ".json'";
  }
  const std::string common =
      "reconcile" + scenes + " --size 32x24 --conventions zo --depth-formats 32f --images none ";
  const auto whole = runClipray(common + "--out whole", folder.path());
  ASSERT_EQ(whole.status, 0) << whole.err;
  const Pairs all = pairsOf(nlohmann::json::parse(readText(folder.path() / "whole/report.json")));
  Pairs united;
  int nonEmpty = 0;
  for (int shard = 1; shard <= 3; ++shard) {
    const std::string out = "shard" + std::to_string(shard);
    const auto result =
        runClipray(common + "--shard " + std::to_string(shard) + "/3 --out " + out, folder.path());
    ASSERT_EQ(result.status, 0) << result.err;
    const auto report = nlohmann::json::parse(readText(folder.path() / out / "report.json"));
    EXPECT_EQ(report["shard"], (nlohmann::json{{"index", shard}, {"count", 3}}));
    const Pairs pairs = pairsOf(report);
    nonEmpty += pairs.empty() ? 0 : 1;
    united.insert(pairs.begin(), pairs.end());
    // The same split on a second asking: it depends on the names only.
    const auto again = runClipray(
        common + "--shard " + std::to_string(shard) + "/3 --out again" + std::to_string(shard),
        folder.path());
    EXPECT_EQ(pairsOf(nlohmann::json::parse(
                  readText(folder.path() / ("again" + std::to_string(shard)) / "report.json"))),
              pairs);
  }
  EXPECT_EQ(all.size(), 9u);
  EXPECT_EQ(united, all);
  EXPECT_EQ(nonEmpty, 3);  // 9 pairs split 5, 3 and 1 by their names
}

TEST(Shards, BadShardValuesAreRefused) {
  TempFolder folder;
  const std::string scene = " '" + kSource + "/scenes/standard.json'";
  for (const char* value : {"4/3", "0/3", "1/0", "abc", "1/3/5", "2", "1/100001"}) {
    SCOPED_TRACE(value);
    const auto result =
        runClipray(std::string("reconcile") + scene + " --shard '" + value + "'", folder.path());
    EXPECT_EQ(result.status, 2);
    EXPECT_EQ(result.err,
              std::string("clipray: --shard: expected I/N with 1 <= I <= N (e.g. 2/8 for the "
                          "second of eight jobs), got \"") +
                  value + "\"\n");
    EXPECT_TRUE(std::filesystem::is_empty(folder.path()));
  }
}

}  // namespace
}  // namespace clipray

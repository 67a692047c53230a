// `clipray reconcile --samples N`: each sample of a multisampled frame is a run of its own,
// compared with rays through its position; counts the implementation does not offer and what
// cannot be multisampled are refused before anything is written.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;

TEST(MultisampleCli, EverySampleIsARunOfItsOwnAndTheReportSaysWhere) {
  TempFolder folder;
  const auto result = runClipray("reconcile '" + kSource +
                                     "/scenes/standard.json' --conventions zo-reversed-upper-left "
                                     "--depth-formats 24 --size 160x120 --samples 4 --out out "
                                     "--junit junit.xml",
                                 folder.path());
  ASSERT_EQ(result.status, 0) << result.err << result.out;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  ASSERT_EQ(report["runs"].size(), 4u);
  std::set<std::pair<double, double>> positions;
  for (int s = 0; s < 4; ++s) {
    const auto& run = report["runs"][s];
    EXPECT_EQ(run["verdict"], "consistent");
    EXPECT_EQ(run["sample"]["index"], s);
    EXPECT_EQ(run["sample"]["count"], 4);
    positions.insert(
        {run["sample"]["position"][0].get<double>(), run["sample"]["position"][1].get<double>()});
    // The frame's pixels, the same on each of its runs (llvmpipe, Mesa 22.3: as in
    // tests/gl/MultisampleTest.cpp).
    EXPECT_EQ(run["sample"]["frame_pixels"]["pixels"], 160 * 120);
    EXPECT_EQ(run["sample"]["frame_pixels"]["covered"], 10086);
    EXPECT_EQ(run["sample"]["frame_pixels"]["partly_covered"], 151);
    EXPECT_EQ(run["sample"]["frame_pixels"]["unexplained"], 0);
  }
  EXPECT_EQ(positions.size(), 4u);
  EXPECT_NE(result.out.find("zo-reversed-upper-left 24  world sample 2 of 4 160x120"),
            std::string::npos)
      << result.out;
  const std::string junit = testing::readText(folder.path() / "junit.xml");
  EXPECT_NE(junit.find("name=\"main zo-reversed-upper-left 24 world sample 3 of 4\""),
            std::string::npos)
      << junit;
}

// A scene whose app draws with MSAA says so ("samples"): its runs are multisampled without the
// option, and --samples overrides it.
TEST(MultisampleCli, AScenesOwnSampleCountIsUsedUnlessTheOptionSetsOne) {
  TempFolder folder;
  const auto writeScene = [&](int samples) {
    nlohmann::json scene =
        nlohmann::json::parse(testing::readText(kSource + "/scenes/standard.json"));
    scene["samples"] = samples;
    std::ofstream(folder.path() / "msaa.json") << scene.dump(1);
  };
  writeScene(4);
  const std::string command =
      "reconcile msaa.json --conventions zo-reversed-upper-left --depth-formats 24 --size 160x120 ";
  auto result = runClipray(command + "--out out", folder.path());
  ASSERT_EQ(result.status, 0) << result.err << result.out;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  ASSERT_EQ(report["runs"].size(), 4u);
  // The same frame as --samples 4 draws (EverySampleIsARunOfItsOwnAndTheReportSaysWhere).
  EXPECT_EQ(report["runs"][2]["sample"]["frame_pixels"]["covered"], 10086);
  EXPECT_EQ(report["runs"][2]["sample"]["frame_pixels"]["partly_covered"], 151);
  result = runClipray(command + "--samples 1 --out single", folder.path());
  ASSERT_EQ(result.status, 0) << result.err << result.out;
  const auto single =
      nlohmann::json::parse(testing::readText(folder.path() / "single/report.json"));
  ASSERT_EQ(single["runs"].size(), 1u);
  EXPECT_FALSE(single["runs"][0].contains("sample"));
  writeScene(3);
  result = runClipray(command + "--out refused", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.err.find("msaa.json: /samples 3: osmesa ("), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(") offers no 3-sample depth format 24 (it offers 4)"),
            std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "refused/report.json"));
}

TEST(MultisampleCli, ACountTheImplementationDoesNotOfferIsRefusedWithTheCountsItDoes) {
  TempFolder folder;
  const auto result = runClipray(
      "reconcile '" + kSource + "/scenes/standard.json' --samples 3 --out out", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.err.find("--samples 3: osmesa ("), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(") offers no 3-sample depth format 24 (it offers 4)"),
            std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out/report.json"));
}

TEST(MultisampleCli, AnalyticPrimitivesAreRefused) {
  TempFolder folder;
  const std::string scene = kSource + "/scenes/primitives.json";
  const auto result =
      runClipray("reconcile '" + scene + "' --samples 4 --size 32x24 --out out", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.err.find("--samples 4: scene \"primitives\" (" + scene +
                            ") has analytic primitives, which are drawn with one depth per pixel "
                            "(gl_FragDepth at its centre); multisampled runs need triangle meshes "
                            "only"),
            std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out/report.json"));
}

TEST(MultisampleCli, ALogarithmicDepthIsRefused) {
  TempFolder folder;
  const std::string scene = kSource + "/scenes/logarithmic_depth.json";
  const auto result =
      runClipray("reconcile '" + scene + "' --samples 4 --size 32x24 --out out", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.err.find("\" of scene \"logarithmic_depth\" (" + scene +
                            ") draws a logarithmic depth, written by the shader once per pixel "
                            "(gl_FragDepth at its centre); multisampled runs need the projective "
                            "depth"),
            std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out/report.json"));
}

}  // namespace
}  // namespace clipray

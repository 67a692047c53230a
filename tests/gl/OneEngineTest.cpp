// `clipray reconcile` and clipray::reconcile run the same plan through the same runner
// (engine/ReconcileRunner.hpp): for the same scene and options they write the same report.json,
// timings aside, and the same images byte for byte. The library is given a ray function (the
// app's picking, here clipray's robust rays): the ray path's alone, as `--analytic rays` is.

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clipray/Reconcile.hpp"
#include "support/GlFixture.hpp"
#include "support/RunCommand.hpp"

namespace clipray {
namespace {

namespace fs = std::filesystem;

// What differs between two runs of the same plan: the clocks and where the command came from.
nlohmann::json withoutTimes(nlohmann::json value) {
  static const std::set<std::string> kTimes = {
      "started_at", "command_line",           "git_commit",         "timings_ms",
      "cpu_ms",     "first_round_timings_ms", "first_round_cpu_ms", "analytic_over_raster"};
  if (value.is_object()) {
    nlohmann::json kept = nlohmann::json::object();
    for (auto& [key, item] : value.items()) {
      if (!kTimes.count(key)) kept[key] = withoutTimes(item);
    }
    return kept;
  }
  if (value.is_array()) {
    for (auto& item : value) item = withoutTimes(item);
  }
  return value;
}

std::set<std::string> pngsUnder(const fs::path& root) {
  std::set<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.path().extension() == ".png") found.insert(fs::relative(entry.path(), root).string());
  }
  return found;
}

// Two cameras (one with an oblique near plane), meshes and a sphere, under the scene's own
// conventions (no, zo) and two depth formats; every run's images.
TEST(OneEngine, CliAndLibraryWriteTheSameReportAndImages) {
  const std::string scenePath = std::string(CLIPRAY_SOURCE_DIR) + "/scenes/water_reflection.json";
  const std::string backend = testing::glBackendForTests();
  testing::TempFolder folder;
  const fs::path cliOut = folder.path() / "cli";
  const fs::path libraryOut = folder.path() / "library";

  const testing::CommandResult cli = testing::runClipray(
      "reconcile '" + scenePath + "' --backend " + backend +
          " --depth-formats 24,32f --analytic rays --images all --out '" + cliOut.string() + "'",
      folder.path());
  ASSERT_LE(cli.status, 1) << cli.err;

  ReconcileOptions options;
  options.backend = backend;
  options.depthFormats = {DepthFormat::Unorm24, DepthFormat::Float32};
  options.reportDirectory = libraryOut.string();
  options.imagesForEveryRun = true;
  const ReconcileResult library = reconcile(TestScene::load(scenePath), robustPickRays(), options);
  ASSERT_EQ(library.runs.size(), 2u * 2u * 2u);  // two cameras x two conventions x two formats
  EXPECT_TRUE(library.consistent()) << library.text();
  EXPECT_EQ(cli.status, 0) << cli.out;
  for (const RunResult& run : library.runs) EXPECT_EQ(run.images.size(), 4u) << run.summaryLine;

  const auto report = [](const fs::path& out) {
    return withoutTimes(nlohmann::json::parse(testing::readText(out / "report.json")));
  };
  EXPECT_EQ(report(cliOut), report(libraryOut));

  const std::set<std::string> pngs = pngsUnder(cliOut);
  EXPECT_EQ(pngs.size(), 8u * 6u);  // four full-size images and two thumbnails per run
  EXPECT_EQ(pngs, pngsUnder(libraryOut));
  for (const std::string& png : pngs) {
    EXPECT_TRUE(testing::readText(cliOut / png) == testing::readText(libraryOut / png)) << png;
  }
}

}  // namespace
}  // namespace clipray

// `clipray reconcile --kernels portable` and `--analytic screen` write what the SIMD kernels on the
// ray path write: every shipped scene under every convention and depth format, report.json equal
// but for what is measured (timings) or stamped (command line, start time), and every other file
// byte for byte (random scenes through the hard-case cameras are checked in process:
// tests/gl/KernelSamenessTest.cpp, tests/unit/ScreenEvaluatorTest.cpp).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "support/RunCommand.hpp"
#include "support/Sanitizers.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;

// Every file under folder by its path relative to it, with its bytes.
std::map<std::string, std::string> filesUnder(const std::filesystem::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    files[std::filesystem::relative(entry.path(), folder).string()] =
        testing::readText(entry.path());
  }
  return files;
}

nlohmann::json withoutMeasurements(nlohmann::json report) {
  report.erase("command_line");
  report.erase("started_at");
  for (auto& run : report["runs"]) {
    // How the analytic side was timed and, on the screen path, which pixels it traced.
    for (const char* measured : {"timings_ms", "cpu_ms", "analytic_over_raster", "screen_path"}) {
      run.erase(measured);
    }
  }
  return report;
}

// Every file of `other` as `base` wrote it, but for what is measured or stamped.
void expectTheSameOutput(const std::filesystem::path& base, const std::filesystem::path& other,
                         const std::string& what) {
  std::map<std::string, std::string> baseFiles = filesUnder(base);
  std::map<std::string, std::string> otherFiles = filesUnder(other);
  const auto baseReport = nlohmann::json::parse(baseFiles.at("report.json"));
  const auto otherReport = nlohmann::json::parse(otherFiles.at("report.json"));
  ASSERT_GT(baseReport["runs"].size(), testing::kUnderAddressSanitizer ? 40u : 200u);
  const nlohmann::json patch =
      nlohmann::json::diff(withoutMeasurements(baseReport), withoutMeasurements(otherReport));
  EXPECT_TRUE(patch.empty()) << what << ": report.json differs by " << patch;
  // index.html shows the timings and the command line; the lock file is the output folder's.
  for (const char* measured : {"report.json", "index.html", ".clipray.lock"}) {
    baseFiles.erase(measured);
    otherFiles.erase(measured);
  }
  ASSERT_EQ(baseFiles.size(), otherFiles.size()) << what;
  int images = 0;
  for (const auto& [path, bytes] : baseFiles) {
    const auto found = otherFiles.find(path);
    ASSERT_NE(found, otherFiles.end()) << path << " is missing from " << what;
    EXPECT_TRUE(bytes == found->second) << what << ": " << path << " differs";
    images += path.ends_with(".png") ? 1 : 0;
  }
  // Every run's four images and two thumbnails, and crops.
  EXPECT_GT(images, 4 * (testing::kUnderAddressSanitizer ? 40 : 200)) << what;
}

// The portable code and the screen path (--analytic screen, ScreenEvaluator.hpp) against the
// default, the SIMD kernels on the ray path.
TEST(KernelSamenessCli,
     ThePortableCodeAndTheScreenPathWriteWhatTheKernelsWriteForEveryShippedScene) {
  TempFolder folder;
  // Under AddressSanitizer (ten times slower) the conventions and formats most runs differ by,
  // a third of the sweep: what it adds is the check of the kernels' memory accesses.
  const std::string sweep = testing::kUnderAddressSanitizer
                                ? "--conventions zo,zo-reversed --depth-formats 24 "
                                : "--conventions no,zo,zo-reversed --depth-formats 16,24,32f ";
  const std::string common = "reconcile '" + kSource + "'/scenes/*.json " + sweep +
                             "--vertex-modes world --images all --threads 2";
  for (const char* choice : {"--kernels simd", "--kernels portable", "--analytic screen"}) {
    const std::string folderName = std::string(choice).substr(std::string(choice).find(' ') + 1);
    const auto result = runClipray(common + " " + choice + " --out " + folderName, folder.path());
    // 1: some runs are inconsistent (reflection matrices drawn reversed, 16-bit depth under an
    // infinite far plane), and that is part of what must come out the same.
    ASSERT_EQ(result.status, 1) << choice << ": " << result.err;
  }
  expectTheSameOutput(folder.path() / "simd", folder.path() / "portable", "the portable code");
  expectTheSameOutput(folder.path() / "simd", folder.path() / "screen", "the screen path");
  // The screen path evaluated the scenes it covers (meshes drawn alike: no analytic primitives,
  // clip planes, depth clamp or objects with state of their own), the hard cases among them
  // included, and no bound failed; it says why it left a frame to the ray path.
  const nlohmann::json screen =
      nlohmann::json::parse(testing::readText(folder.path() / "screen" / "report.json"));
  const std::set<std::string> covered = {
      "standard",        "terrain_100k",          "grazing_floor", "near_plane_straddle",
      "far_from_origin", "ortho_far_from_origin", "infinite_far",  "coplanar"};
  std::size_t evaluated = 0;
  for (const nlohmann::json& run : screen["runs"]) {
    const std::string scene = run["scene"];
    ASSERT_TRUE(run.contains("screen_path")) << scene;
    const nlohmann::json& path = run["screen_path"];
    EXPECT_TRUE(!covered.contains(scene) || !path.contains("declined")) << scene;
    if (scene == "primitives") {
      EXPECT_EQ(path, nlohmann::json({{"declined", "analytic primitives stay on rays"}}));
    }
    if (scene == "object_depth_range") {
      EXPECT_EQ(path,
                nlohmann::json({{"declined",
                                 "objects with draw state of their own (2 groups) stay on rays"}}));
    }
    if (path.contains("declined")) continue;
    ++evaluated;
    EXPECT_EQ(path["bound_misses"], 0) << scene;
    EXPECT_EQ(path["background"].get<std::int64_t>() + path["decided"].get<std::int64_t>() +
                  path["contested"].get<std::int64_t>() + path["traced"].get<std::int64_t>(),
              run["pixels"].get<std::int64_t>())
        << scene;
  }
  EXPECT_GT(evaluated, testing::kUnderAddressSanitizer ? 30u : 100u);
}

TEST(KernelSamenessCli, AnUnknownAnalyticPathIsRefused) {
  TempFolder folder;
  const auto result =
      runClipray("reconcile '" + kSource + "'/scenes/standard.json --analytic raster --out out",
                 folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: --analytic: unknown value \"raster\"; expected one of: rays, screen\n");
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out"));
}

}  // namespace
}  // namespace clipray

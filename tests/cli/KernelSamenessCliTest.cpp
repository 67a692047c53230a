// `clipray reconcile --kernels portable` writes what the SIMD kernels write, on either analytic
// path (`--analytic rays`, `--analytic screen`): every shipped scene under every convention and
// depth format, report.json equal but for what is measured (timings) or stamped (command line,
// start time), and every other file byte for byte. The screen path classifies every pixel as the
// ray path does, its depth figures computed from the triangles' planes instead of the rays' hits:
// the same report but for those figures, which lie within a hair of the ray path's, the same images
// but for the error heat maps and depth images, whose colours move by one level at most where a
// value lies at a rounding step, the same summary but for those figures and the order of runs
// sorted by one (random scenes through the hard-case cameras are checked in
// process: tests/gl/KernelSamenessTest.cpp, tests/gl/ScreenPathSamenessTest.cpp,
// tests/unit/ScreenEvaluatorTest.cpp).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include "support/DecodedPng.hpp"
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

// How `other` may differ from `base`: not at all, or (the screen path) in the depth figures the
// planes compute and in the heat maps drawn from them.
enum class Figures { Equal, WithinAHair };

// The report with every float figure replaced by 0 (what must then be equal), and the figures
// apart, at most, relative to themselves.
nlohmann::json withoutFigures(const nlohmann::json& entry) {
  if (entry.is_number_float()) return 0.0;
  nlohmann::json out = entry;
  if (entry.is_object() || entry.is_array()) {
    for (auto& value : out) value = withoutFigures(value);
  }
  return out;
}
double figuresApart(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_number_float() && b.is_number_float()) {
    const double x = a.get<double>(), y = b.get<double>();
    return std::abs(x - y) / std::max({std::abs(x), std::abs(y), 1e-300});
  }
  double apart = 0.0;
  if ((a.is_object() || a.is_array()) && a.size() == b.size()) {
    for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j) {
      apart = std::max(apart, figuresApart(*i, *j));
    }
  }
  return apart;
}

// The largest difference of a channel between two PNGs of the same size (256 if they differ in
// size or do not decode).
int channelsApart(const std::string& a, const std::string& b) {
  using Rgb = std::array<std::uint8_t, 3>;
  const auto x = testing::decodePng<Rgb>(a), y = testing::decodePng<Rgb>(b);
  if (x.width != y.width || x.height != y.height || x.rgb.size() != y.rgb.size()) return 256;
  int apart = 0;
  for (std::size_t i = 0; i < x.rgb.size(); ++i) {
    apart = std::max(apart, std::abs(int{x.rgb[i]} - int{y.rgb[i]}));
  }
  return apart;
}

// summary.txt's lines with each decimal figure written as '#', in order: the screen path's summary
// (whose figures report.json checks within a hair) lists the same runs, but two whose sorting
// figure lies within a hair may trade places.
std::vector<std::string> linesWithoutFigures(const std::string& text) {
  static const std::regex decimal(R"(-?\d+\.\d*(e[-+]?\d+)?|-?\d+e[-+]?\d+)");
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    lines.push_back(std::regex_replace(line, decimal, "#"));
  }
  std::sort(lines.begin(), lines.end());
  return lines;
}

// Every file of `other` as `base` wrote it, but for what is measured or stamped.
void expectTheSameOutput(const std::filesystem::path& base, const std::filesystem::path& other,
                         const std::string& what, Figures figures = Figures::Equal) {
  std::map<std::string, std::string> baseFiles = filesUnder(base);
  std::map<std::string, std::string> otherFiles = filesUnder(other);
  const auto baseReport = nlohmann::json::parse(baseFiles.at("report.json"));
  const auto otherReport = nlohmann::json::parse(otherFiles.at("report.json"));
  ASSERT_GT(baseReport["runs"].size(), testing::kUnderAddressSanitizer ? 40u : 200u);
  const nlohmann::json patch =
      figures == Figures::Equal
          ? nlohmann::json::diff(withoutMeasurements(baseReport), withoutMeasurements(otherReport))
          : nlohmann::json::diff(withoutFigures(withoutMeasurements(baseReport)),
                                 withoutFigures(withoutMeasurements(otherReport)));
  EXPECT_TRUE(patch.empty()) << what << ": report.json differs by " << patch;
  if (figures == Figures::WithinAHair) {
    // Differences of nearly equal depths (error over tolerance or quantum, distances apart) move
    // by the depths' difference (below 10^-9 of the depth range) over themselves.
    EXPECT_LT(figuresApart(withoutMeasurements(baseReport), withoutMeasurements(otherReport)), 0.01)
        << what;
  }
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
    if (figures == Figures::WithinAHair &&
        (path.ends_with("heatmap.png") || path.ends_with("depth.png"))) {
      // Drawn from error / tolerance (continuous but for the step at 1, where the classes, equal,
      // keep both sides apart) or from the depths over the range both sides share: a hair's move
      // changes a channel's rounding by one level at most.
      EXPECT_LE(channelsApart(bytes, found->second), 1) << what << ": " << path;
    } else if (figures == Figures::WithinAHair && path == "summary.txt") {
      EXPECT_EQ(linesWithoutFigures(bytes), linesWithoutFigures(found->second)) << what;
    } else {
      EXPECT_TRUE(bytes == found->second) << what << ": " << path << " differs";
    }
    images += path.ends_with(".png") ? 1 : 0;
  }
  // Every run's four images and two thumbnails, and crops.
  EXPECT_GT(images, 4 * (testing::kUnderAddressSanitizer ? 40 : 200)) << what;
}

// The portable code against the SIMD kernels on both paths, and the screen path
// (ScreenEvaluator.hpp, the default) against the ray path: the same classes and counts.
TEST(KernelSamenessCli,
     ThePortableCodeWritesWhatTheKernelsWriteAndTheScreenPathClassifiesAsTheyDo) {
  TempFolder folder;
  // Under AddressSanitizer (ten times slower) the conventions and formats most runs differ by,
  // a third of the sweep: what it adds is the check of the kernels' memory accesses.
  const std::string sweep = testing::kUnderAddressSanitizer
                                ? "--conventions zo,zo-reversed --depth-formats 24 "
                                : "--conventions no,zo,zo-reversed --depth-formats 16,24,32f ";
  const std::string common = "reconcile '" + kSource + "'/scenes/*.json " + sweep +
                             "--vertex-modes world --images all --threads 2";
  const std::pair<const char*, const char*> choices[] = {
      {"--analytic rays --kernels simd", "rays"},
      {"--analytic rays --kernels portable", "rays-portable"},
      {"--analytic screen --kernels simd", "screen"},
      {"--analytic screen --kernels portable", "screen-portable"}};
  for (const auto& [choice, folderName] : choices) {
    const auto result = runClipray(common + " " + choice + " --out " + folderName, folder.path());
    // 1: some runs are inconsistent (reflection matrices drawn reversed, 16-bit depth under an
    // infinite far plane), and that is part of what must come out the same.
    ASSERT_EQ(result.status, 1) << choice << ": " << result.err;
  }
  expectTheSameOutput(folder.path() / "rays", folder.path() / "rays-portable", "the portable code");
  expectTheSameOutput(folder.path() / "rays", folder.path() / "screen", "the screen path",
                      Figures::WithinAHair);
  // The screen path's figures are the same bits under either kernel choice.
  expectTheSameOutput(folder.path() / "screen", folder.path() / "screen-portable",
                      "the screen path's portable code");
  // The screen path evaluated the scenes it covers (meshes, with or without analytic primitives,
  // with or without depth clamp), the hard cases, user clip planes and objects with state of their
  // own (a frame per group) among them, and no bound failed; it says why it left a frame to the ray
  // path.
  const nlohmann::json screen =
      nlohmann::json::parse(testing::readText(folder.path() / "screen" / "report.json"));
  const std::set<std::string> covered = {
      "standard",           "terrain_100k",          "grazing_floor", "near_plane_straddle",
      "far_from_origin",    "ortho_far_from_origin", "infinite_far",  "coplanar",
      "object_clip_planes", "object_depth_range",    "polygon_offset"};
  std::size_t evaluated = 0;
  for (const nlohmann::json& run : screen["runs"]) {
    const std::string scene = run["scene"];
    ASSERT_TRUE(run.contains("screen_path")) << scene;
    const nlohmann::json& path = run["screen_path"];
    EXPECT_TRUE(!covered.contains(scene) || !path.contains("declined")) << scene;
    // The mirrored camera's matrices are built for NO and ZO; reversed, their near plane lies on
    // the eye's visible side, and no bound holds for their rays.
    if (scene == "water_reflection" && run["camera"] == "reflection_zo" &&
        run["convention"] == "no") {
      // Where the oblique near plane leaves the screen bins a bound (the ZO-built matrix drawn
      // under NO): the meshes decided, the pixels around the buoy (a sphere) traced.
      EXPECT_FALSE(path.contains("declined")) << scene;
      EXPECT_GT(path.value("traced", 0), 1000) << scene;
      EXPECT_GT(path.value("decided", 0), 10000) << scene;
    }
    if (scene == "water_reflection_clipped" && run["convention"] != "zo-reversed") {
      EXPECT_FALSE(path.contains("declined")) << scene << " " << run["convention"];
    }
    if (scene == "primitives") {
      EXPECT_EQ(path, nlohmann::json({{"declined", "analytic primitives stay on rays"}}));
    }
    if (scene == "depth_clamp") {
      // Depth clamp's rays start at the eye: the barrel in front of the near plane is decided too
      // (its pixels are those in front of near).
      EXPECT_FALSE(path.contains("declined")) << scene << " " << run["convention"];
      EXPECT_GT(path.value("decided", 0), run.value("in_front_of_near", 0)) << scene;
      EXPECT_LT(path.value("traced", 0) * 100, path.value("decided", 0)) << scene;
    }
    if (scene == "logarithmic_depth") {
      // A perspective camera's logarithmic depth is compared from the plane of 1 / w: all but the
      // few pixels whose class or quantum its reach leaves open.
      EXPECT_GT(path.value("compared_from_planes", 0) * 100, path.value("decided", 0) * 99)
          << scene << " " << run["camera"] << " " << run["convention"];
    }
    if (path.contains("declined")) continue;
    ++evaluated;
    EXPECT_EQ(path["bound_misses"], 0) << scene;
    // Objects drawn with state of their own: a frame per group, each counted whole.
    const std::int64_t frames = scene.starts_with("object_") || scene == "polygon_offset" ? 2 : 1;
    EXPECT_EQ(path.value("frames", std::int64_t{1}), frames) << scene;
    EXPECT_EQ(path.value("groups", std::int64_t{1}), frames) << scene;
    EXPECT_EQ(path["background"].get<std::int64_t>() + path["decided"].get<std::int64_t>() +
                  path["contested"].get<std::int64_t>() + path["traced"].get<std::int64_t>(),
              frames * run["pixels"].get<std::int64_t>())
        << scene;
  }
  EXPECT_GT(evaluated, testing::kUnderAddressSanitizer ? 30u : 100u);
}

// --analytic auto (the default) takes the screen path where a frame has 16 pixels or more for each
// triangle, and says why it left the others to the rays: the 100,352-triangle terrain at 320x240
// (76,800 pixels) on rays, at 1280x1024 (1,310,720, 13.1 a triangle) too, the standard scene's
// few thousand triangles at 320x240 on the screen path.
TEST(KernelSamenessCli, AutoTakesTheScreenPathWhereTheFrameHasSixteenPixelsATriangle) {
  TempFolder folder;
  const auto reportOf = [&](const std::string& arguments) {
    const auto result = runClipray("reconcile " + arguments +
                                       " --conventions zo --depth-formats 32f "
                                       "--images none --out out",
                                   folder.path());
    EXPECT_EQ(result.status, 0) << result.err;
    return nlohmann::json::parse(testing::readText(folder.path() / "out" / "report.json"));
  };
  const std::string terrain = "'" + kSource + "'/scenes/terrain_100k.json";
  for (const auto& [size, pixels] :
       {std::pair<const char*, const char*>{"320x240", "76800"}, {"1280x1024", "1310720"}}) {
    const nlohmann::json report = reportOf(terrain + " --size " + size);
    EXPECT_EQ(report["runs"].at(0)["screen_path"],
              nlohmann::json({{"declined", std::string("100352 triangles for ") + pixels +
                                               " pixels: the rays are faster below 16 pixels a "
                                               "triangle"}}))
        << size;
  }
  const nlohmann::json standard = reportOf("'" + kSource + "'/scenes/standard.json --size 320x240");
  EXPECT_GT(standard["runs"].at(0)["screen_path"]["decided"].get<std::int64_t>(), 10000);
  // Objects drawn with state of their own: each group chosen on its own triangles. At 16x12 the
  // weapon's 12 triangles (192 pixels: 16 a triangle) take the screen path, the world's 16 the
  // rays; at 8x6 neither does, and the first group's reason is given.
  const std::string groups = "'" + kSource + "'/scenes/object_depth_range.json";
  const nlohmann::json oneOfTwo = reportOf(groups + " --size 16x12");
  const nlohmann::json& path = oneOfTwo["runs"].at(0)["screen_path"];
  EXPECT_EQ(path["frames"], 1);
  EXPECT_EQ(path["groups"], 2);
  EXPECT_EQ(path["background"].get<std::int64_t>() + path["decided"].get<std::int64_t>() +
                path["contested"].get<std::int64_t>() + path["traced"].get<std::int64_t>(),
            192);
  EXPECT_EQ(reportOf(groups + " --size 8x6")["runs"].at(0)["screen_path"],
            nlohmann::json({{"declined",
                             "objects with draw state of their own (2 groups), none on the screen "
                             "path: 16 triangles for 48 pixels: the rays are faster below 16 "
                             "pixels a triangle"}}));
}

TEST(KernelSamenessCli, AnUnknownAnalyticPathIsRefused) {
  TempFolder folder;
  const auto result =
      runClipray("reconcile '" + kSource + "'/scenes/standard.json --analytic raster --out out",
                 folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: --analytic: unknown value \"raster\"; expected one of: auto, rays, screen\n");
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out"));
}

}  // namespace
}  // namespace clipray

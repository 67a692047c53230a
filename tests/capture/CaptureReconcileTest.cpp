// `clipray reconcile --capture` on RenderDoc captures of the trace-test apps
// (tests/traceapps/ConventionApp.cpp, captured as CaptureApps.hpp does): the frame's own depth
// buffer against the rays of the camera matrix in its uniforms, traced under what the matrix was
// built for (engine/CaptureReconcile.hpp). Each app draws one frame into a 64x48 float depth
// buffer: its triangle covers 56 pixels, and in the overlap cases a larger triangle behind it
// brings the frame to 516. A correct app is consistent; each classic mistake shows as the pixels
// where what GL drew differs from what the matrix meant: NO drawn under ZERO_TO_ONE stores every
// covered pixel's depth at the wrong place (56 beyond tolerance), GL_CCW left under a y-flipped
// projection culls the outside (56 pixels the rays hit and the raster does not), reversed-Z under
// GL_LESS shows the triangle behind over the one in front (56 pixels of the wrong draw).

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "capture/CaptureApps.hpp"
#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::captureCase;
using testing::runClipray;
using testing::TempFolder;

struct ReconcileCase {
  std::string name;
  int status = 0;
  std::string verdict, convention;
  std::int64_t rasterHits = 0, rayHits = 0;
  std::int64_t coverageUnexplained = 0, idUnexplained = 0, beyondTolerance = 0;
};

void PrintTo(const ReconcileCase& c, std::ostream* out) {
  *out << c.name;
}

class CaptureReconcileCase : public ::testing::TestWithParam<ReconcileCase> {};

TEST_P(CaptureReconcileCase, ComparesTheCapturedDepthWithTheCamerasRays) {
  const ReconcileCase& expected = GetParam();
  TempFolder folder;
  ASSERT_EQ(captureCase(expected.name, folder), "");
  const auto result =
      runClipray("reconcile --capture " + expected.name + ".rdc --out out --json", folder.path());
  ASSERT_EQ(result.status, expected.status) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report["runs"].size(), 1u);
  const nlohmann::json& run = report["runs"][0];
  EXPECT_EQ(run["verdict"], expected.verdict);
  EXPECT_EQ(run["scene"], expected.name);
  EXPECT_EQ(run["convention"], expected.convention);
  EXPECT_EQ(run["depth_format"], "32f");
  EXPECT_EQ(run["size"], (nlohmann::json{{"width", 64}, {"height", 48}}));
  EXPECT_EQ(run["raster_hits"], expected.rasterHits);
  EXPECT_EQ(run["ray_hits"], expected.rayHits);
  EXPECT_EQ(run["coverage_mismatch"]["unexplained"], expected.coverageUnexplained);
  EXPECT_EQ(run["id_mismatch"]["unexplained"], expected.idUnexplained);
  EXPECT_EQ(run["depth_beyond_tolerance"], expected.beyondTolerance);
  EXPECT_EQ(report["gl"]["backend"], "renderdoc");
  // The first note says what the rays were traced under and what the capture holds.
  const std::string note = run["notes"][0];
  EXPECT_TRUE(note.starts_with("rays traced under " + expected.convention + ", the convention "))
      << note;
  // The scene report's files, as a scene's reconcile writes them.
  for (const char* file : {"index.html", "report.json", "summary.txt"}) {
    EXPECT_TRUE(std::filesystem::exists(folder.path() / "out" / file)) << file;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Apps, CaptureReconcileCase,
    ::testing::Values(
        ReconcileCase{"zo", 0, "consistent", "zo", 56, 56, 0, 0, 0},
        ReconcileCase{"no-under-zo", 1, "inconsistent", "no", 56, 56, 0, 0, 56},
        ReconcileCase{"d3d-style-culled", 0, "consistent", "zo-upper-left", 56, 56, 0, 0, 0},
        ReconcileCase{"d3d-style-culled-ccw", 1, "inconsistent", "zo-upper-left", 0, 56, 56, 0, 0},
        ReconcileCase{"overlap-reversed", 0, "consistent", "zo-reversed", 516, 516, 0, 0, 0},
        // The shadow map's draw (its own depth buffer, cleared, 32x32) is not the frame's.
        ReconcileCase{"zo-shadow-pass", 0, "consistent", "zo", 56, 56, 0, 0, 0},
        ReconcileCase{"overlap-reversed-with-less", 1, "inconsistent", "zo-reversed", 516, 516, 0,
                      56, 0},
        // One triangle: nothing lies behind it for GL_LESS to keep instead, so the pixels agree
        // and the check's errors on the captured state decide.
        ReconcileCase{"reversed-with-less", 1, "convention-error", "zo-reversed", 56, 56, 0, 0, 0}),
    [](const ::testing::TestParamInfo<ReconcileCase>& param) {
      std::string name = param.param.name;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// The pixels named: where the triangle behind shows over the one in front, each side's draw.
TEST(CaptureReconcile, NamesTheDrawEachSideShows) {
  TempFolder folder;
  ASSERT_EQ(captureCase("overlap-reversed-with-less", folder), "");
  const auto result =
      runClipray("reconcile --capture overlap-reversed-with-less.rdc --out out", folder.path());
  ASSERT_EQ(result.status, 1) << result.err;
  const nlohmann::json report =
      nlohmann::json::parse(testing::readText(folder.path() / "out" / "report.json"));
  const nlohmann::json& worst = report["runs"][0]["worst_pixel"];
  EXPECT_EQ(worst["class"], "id_unexplained");
  const std::string raster = worst["raster"]["object"], ray = worst["ray"]["object"];
  // The first draw (the triangle in front) is what the rays hit; the second what GL kept.
  ASSERT_TRUE(ray.starts_with("draw ") && raster.starts_with("draw ")) << ray << " " << raster;
  EXPECT_LT(std::stoi(ray.substr(5)), std::stoi(raster.substr(5)));
  // Reversed-Z: the surface in front has the greater depth.
  EXPECT_GT(worst["ray"]["depth"].get<double>(), worst["raster"]["depth"].get<double>());
  EXPECT_NE(result.out.find("cluster 1 (56 px)"), std::string::npos) << result.out;
}

// Every option that cannot go with a capture is refused, naming it, before anything is read.
TEST(CaptureReconcile, RefusesWhatACaptureCannotTake) {
  TempFolder folder;
  ASSERT_EQ(captureCase("zo", folder), "");
  const std::pair<std::string, std::string> cases[] = {
      {"--capture zo.rdc scenes.json",
       "--capture: the capture is the scene; give no scene files (got scenes.json)"},
      {"--capture zo.rdc --conventions no",
       "--conventions: not with --capture (the capture holds the frame)"},
      {"--draws 1-5", "--draws needs --capture"},
      {"--capture zo.rdc --draws 1-2",
       "zo.rdc: --draws 1-2: no draw in that range (the capture's 1 draws are events "},
      {"--capture missing.rdc", "missing.rdc"},
  };
  for (const auto& [arguments, message] : cases) {
    const auto result = runClipray("reconcile " + arguments + " --out out", folder.path());
    EXPECT_EQ(result.status, 2) << arguments;
    EXPECT_NE(result.err.find(message), std::string::npos) << arguments << ": " << result.err;
    EXPECT_FALSE(std::filesystem::exists(folder.path() / "out")) << arguments;
  }
}

}  // namespace
}  // namespace clipray

// `clipray reconcile --page` on the three.js test pages (tests/webgl/three/, three.js 0.187.0
// from npm: harness/install-deps.sh runs `npm ci` there), in Debian's chromium headless on
// SwiftShader: the page's own Raycaster.setFromCamera at 32x24 pixel centres against its depth
// buffer, and the state check (`clipray check --page`) of the same recording. Every page draws
// the same four meshes (a ground plane, three boxes and a small box in front of the green one) at
// 320x240: 768 picks, of which 264 (perspective) or 128 (orthographic) see only the clear colour.
// Each page costs one browser start (a few seconds).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

namespace fs = std::filesystem;
using testing::runClipray;
using testing::TempFolder;

std::string threePage(const std::string& name) {
  return std::string(CLIPRAY_SOURCE_DIR) + "/tests/webgl/three/" + name;
}

void requireThree() {
  ASSERT_TRUE(fs::exists(threePage("node_modules/three/build/three.module.js")))
      << "three.js is not installed in tests/webgl/three: run harness/install-deps.sh (npm ci)";
}

// The class counts of a reconcile --page report, as "agree S+B >tol e/u ray-only e/u
// raster-only e/u".
std::string classes(const nlohmann::json& picks) {
  const auto pair = [&](const char* key) {
    return std::to_string(picks[key]["edge_ambiguous"].get<int>()) + "/" +
           std::to_string(picks[key]["unexplained"].get<int>());
  };
  return "agree " + std::to_string(picks["agree"]["surface"].get<int>()) + "+" +
         std::to_string(picks["agree"]["background"].get<int>()) + " >tol " +
         pair("depth_beyond_tolerance") + " ray-only " + pair("ray_only") + " raster-only " +
         pair("raster_only");
}

// "severity:code" of the one group's findings, or "not checked: ..." for the canvas.
std::vector<std::string> stateFindings(const nlohmann::json& canvas) {
  if (!canvas.contains("check"))
    return {"not checked: " + canvas["not_checked"].get<std::string>()};
  std::vector<std::string> result;
  const nlohmann::json& groups = canvas["check"]["groups"];
  EXPECT_EQ(groups.size(), 1u);
  EXPECT_EQ(groups[0]["source"], "uniform projectionMatrix (program 1)");
  for (const auto& f : groups[0]["findings"]) {
    result.push_back(f["severity"].get<std::string>() + ":" + f["code"].get<std::string>());
  }
  return result;
}

// The run with reversedDepthBuffer toggled (the page loaded again in the same browser, its
// renderer's depth buffer flipped before its first frame).
struct Toggled {
  int status;  // 0 consistent, 1 inconsistent
  const char* classes;
  std::vector<std::string> findings;
};

struct Expected {
  const char* page;
  int status;  // of the page as it is: 0 consistent, 1 inconsistent
  const char* camera;
  bool reversed;  // reversedDepthBuffer: clip zero-to-one, cleared to 0
  const char* classes;
  std::vector<std::string> findings;
  // None: run with --no-toggle (one load: the CI budget has a toggled run only where it pins
  // something).
  std::optional<Toggled> toggled = std::nullopt;
};

// The depth state and the state check of a run.
void expectRun(const nlohmann::json& run, bool reversed, int status, const char* classesText,
               const std::vector<std::string>& findings) {
  const nlohmann::json& depth = run["depth"];
  EXPECT_EQ(depth["reversed_depth_buffer"], reversed);
  EXPECT_EQ(depth["clip_depth"], reversed ? "zero-to-one" : "negative-one-to-one");
  EXPECT_EQ(depth["clear_depth"], reversed ? 0.0 : 1.0);
  EXPECT_EQ(depth["format"], "GL_DEPTH24_STENCIL8");
  EXPECT_EQ(depth["subpixel_bits"], 4);
  EXPECT_EQ(run["picks"]["total"], 768);
  EXPECT_EQ(classes(run["picks"]), classesText);
  EXPECT_EQ(run["verdict"], status == 0 ? "consistent" : "inconsistent");
  // Every agreeing pick within its tolerance: the largest error over the tolerance is below 1.
  if (status == 0) {
    EXPECT_LT(run["picks"]["max_error_over_tolerance"].get<double>(), 1.0);
  }
  // The state check of the same recording (three frames of five draws).
  const nlohmann::json& state = run["state_check"];
  EXPECT_EQ(state["frames"], 3);
  EXPECT_EQ(state["draws"], 15);
  ASSERT_EQ(state["canvases"].size(), 1u);
  EXPECT_EQ(stateFindings(state["canvases"][0]), findings);
}

// Runs reconcile --page on the page and checks its report; returns the index.html written beside
// it.
std::string expectReconcile(const Expected& e) {
  SCOPED_TRACE(e.page);
  TempFolder folder;
  const auto result = runClipray("reconcile --page '" + threePage(e.page) + "' --json --out out" +
                                     (e.toggled ? "" : " --no-toggle"),
                                 folder.path());
  const int status = std::max(e.status, e.toggled ? e.toggled->status : 0);
  EXPECT_EQ(result.status, status) << result.err;
  if (result.status != status) return "";
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["tool"], "clipray reconcile --page");
  EXPECT_EQ(report["three_revision"], "187");
  EXPECT_EQ(report["canvas"], "canvas#view");
  EXPECT_EQ(report["drawing_buffer"], nlohmann::json::array({320, 240}));
  EXPECT_EQ(report["device_pixel_ratio"], 1.0);
  EXPECT_EQ(report["grid"], nlohmann::json::array({32, 24}));
  EXPECT_EQ(report["camera"]["type"], e.camera);
  expectRun(report, e.reversed, e.status, e.classes, e.findings);
  const nlohmann::json& toggled = report["toggled"];
  EXPECT_EQ(toggled["made"], e.toggled.has_value());
  EXPECT_EQ(toggled["reversed_depth_buffer"], !e.reversed);
  if (e.toggled) {
    SCOPED_TRACE("toggled");
    EXPECT_EQ(toggled["camera"]["type"], e.camera);
    expectRun(toggled, !e.reversed, e.toggled->status, e.toggled->classes, e.toggled->findings);
    EXPECT_NE(result.err.find(std::string("\ntoggled: reversedDepthBuffer ") +
                              (e.reversed ? "off (the page: on)" : "on (the page: off)") +
                              ", the page loaded again with its renderer's depth buffer flipped "
                              "before its first frame\n"),
              std::string::npos)
        << result.err;
  } else {
    EXPECT_EQ(toggled["skipped"], "--no-toggle");
    EXPECT_EQ(toggled["verdict"], nullptr);
  }
  EXPECT_EQ(report["overall"], status == 0 ? "consistent" : "inconsistent");
  // The report written beside the summary, which went to stderr, and index.html with the picks
  // images.
  EXPECT_TRUE(fs::is_regular_file(folder.path() / "out" / "page-report.json"));
  EXPECT_TRUE(fs::is_regular_file(folder.path() / "out" / "index.html"));
  EXPECT_TRUE(fs::is_regular_file(folder.path() / "out" / "picks.png"));
  EXPECT_EQ(fs::is_regular_file(folder.path() / "out" / "picks-toggled.png"),
            e.toggled.has_value());
  EXPECT_NE(result.err.find("report: out/page-report.json (out/index.html beside it)\n"),
            std::string::npos)
      << result.err;
  std::ifstream html(folder.path() / "out" / "index.html");
  return std::string(std::istreambuf_iterator<char>(html), std::istreambuf_iterator<char>());
}

// Correct pages in both depth modes, perspective and orthographic: every pick agrees but one in
// the perspective views, the ray and the raster at an occluding edge of the small box
// (edge-ambiguous: the rays 1/16 pixel around the centre reach different meshes). The perspective
// pages toggled (off to on, on to off) give the other's counts; the other correct pages run with
// --no-toggle (their toggled runs, consistent too, would add a page load each to CI).
TEST(PageReconcileCli, CorrectPagesAreConsistentInBothDepthModes) {
  requireThree();
  expectReconcile({"perspective.html",
                   0,
                   "PerspectiveCamera",
                   false,
                   "agree 503+264 >tol 1/0 ray-only 0/0 raster-only 0/0",
                   {},
                   Toggled{0, "agree 503+264 >tol 1/0 ray-only 0/0 raster-only 0/0", {}}});
  expectReconcile({"perspective-reversed.html",
                   0,
                   "PerspectiveCamera",
                   true,
                   "agree 503+264 >tol 1/0 ray-only 0/0 raster-only 0/0",
                   {},
                   Toggled{0, "agree 503+264 >tol 1/0 ray-only 0/0 raster-only 0/0", {}}});
  // A ShaderMaterial of the page's own: three.js reverses its depthFunc under reversed depth.
  expectReconcile({"shader-reversed.html",
                   0,
                   "PerspectiveCamera",
                   true,
                   "agree 503+264 >tol 1/0 ray-only 0/0 raster-only 0/0",
                   {}});
  // An orthographic NO matrix reads the same built for NO or ZO (near 0.1 either way).
  expectReconcile({"orthographic.html",
                   0,
                   "OrthographicCamera",
                   false,
                   "agree 640+128 >tol 0/0 ray-only 0/0 raster-only 0/0",
                   {"info:depth-convention-ambiguous"}});
  // three.js 0.187's own orthographic Raycaster under reversed depth: right. Its reversed
  // orthographic matrix keeps orientation (z row 1 / (far - near), far / (far - near)): read as a
  // projection in a reversed-Z frame (hasReversedOrthographicStructure), nothing to find.
  expectReconcile({"orthographic-reversed.html",
                   0,
                   "OrthographicCamera",
                   true,
                   "agree 640+128 >tol 0/0 ray-only 0/0 raster-only 0/0",
                   {}});
}

// (a) A reversed-Z camera built by hand on a default renderer, a ShaderMaterial with the default
// depthFunc (LEQUAL) over a depth cleared to 1: where surfaces overlap the farther one wins, so
// the depth the ray's first hit predicts is nearer than the buffer's (76 picks); the state check
// names the mismatch. Toggled on, three.js reverses the ShaderMaterial's depthFunc (GEQUAL), clears
// to 0 under ZERO_TO_ONE and keeps the page's reversed projection (the page disabled
// updateProjectionMatrix): the page as its author meant it, consistent, nothing to find.
// index.html shows both runs.
TEST(PageReconcileCli, ReversedCameraWithTheDefaultDepthFunctionIsInconsistent) {
  requireThree();
  const std::string html =
      expectReconcile({"reversed-camera-default-depth.html",
                       1,
                       "PerspectiveCamera",
                       false,
                       "agree 426+264 >tol 2/76 ray-only 0/0 raster-only 0/0",
                       {"warning:reversed-z-without-zero-to-one", "error:reversed-z-mismatch",
                        "warning:infinite-far-plane", "error:clear-depth-mismatch"},
                       Toggled{0, "agree 503+264 >tol 1/0 ray-only 0/0 raster-only 0/0", {}}});
  EXPECT_NE(html.find("<p id=\"verdict\" class=\"verdict inconsistent\">inconsistent: the page "
                      "as it is inconsistent, reversedDepthBuffer toggled on consistent</p>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<tr><th>three.js</th><td>r187</td></tr>"), std::string::npos);
  EXPECT_NE(html.find("<tr class=\"run inconsistent\" data-run=\"page\"><td>the page as it "
                      "is</td><td class=\"verdict\">inconsistent</td><td class=\"figures\">off, "
                      "negative-one-to-one, cleared to 1, depthRange 0, 1, "
                      "GL_DEPTH24_STENCIL8</td><td class=\"figures\">426+264</td><td "
                      "class=\"figures\">2/76</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<tr class=\"run consistent\" data-run=\"toggled\"><td>reversedDepthBuffer "
                      "toggled on</td>"),
            std::string::npos);
  // The worst picks: the ray's first hit nearer than the surface the buffer kept, by thousands
  // of tolerances.
  EXPECT_NE(html.find("<h3>The worst picks (10 of 78 mismatches; unexplained first, largest "
                      "error over tolerance first)</h3>"),
            std::string::npos);
  EXPECT_NE(html.find("<li data-code=\"reversed-z-mismatch\"><span class=\"error\">error "
                      "reversed-z-mismatch</span>"),
            std::string::npos);
}

// (b) three.js's orthographic ray before reversed depth: its origin at z_ndc = (near + far) /
// (near - far) unprojects beyond the far plane under reversed depth, and every ray misses: each
// of the 640 drawn pixels is raster-only. Toggled off, the old ray is right again: consistent.
TEST(PageReconcileCli, OldOrthographicRaycastUnderReversedDepthMissesEverything) {
  requireThree();
  expectReconcile({"orthographic-raycast-reversed.html",
                   1,
                   "OrthographicCamera",
                   true,
                   "agree 0+128 >tol 0/0 ray-only 0/0 raster-only 0/640",
                   {},
                   Toggled{0,
                           "agree 640+128 >tol 0/0 ray-only 0/0 raster-only 0/0",
                           {"info:depth-convention-ambiguous"}}});
}

// (c) A picker that unprojects z_ndc -1 and 1 as [-1, 1] depth under EXT_clip_control's
// ZERO_TO_ONE: the ray starts beyond the far plane and runs toward the camera, and its first hit
// (double-sided materials) is the farthest surface, not the drawn one, wherever a box stands on
// the ground (112 picks); the bare ground still agrees. Toggled off, [-1, 1] is the page's depth
// and the picker is right: consistent.
TEST(PageReconcileCli, PickerUnprojectingNoDepthUnderZeroToOneHitsTheFarthestSurface) {
  requireThree();
  expectReconcile({"orthographic-picker-no-under-zo.html",
                   1,
                   "OrthographicCamera",
                   true,
                   "agree 501+128 >tol 27/112 ray-only 0/0 raster-only 0/0",
                   {},
                   Toggled{0,
                           "agree 640+128 >tol 0/0 ray-only 0/0 raster-only 0/0",
                           {"info:depth-convention-ambiguous"}}});
}

// `clipray check --page` itself on the three.js pages: the same findings, its own exit statuses.
TEST(PageReconcileCli, CheckPageReadsTheThreePages) {
  requireThree();
  TempFolder folder;
  const auto mistake =
      runClipray("check --page '" + threePage("reversed-camera-default-depth.html") + "' --json",
                 folder.path());
  ASSERT_EQ(mistake.status, 1) << mistake.err;
  const auto report = nlohmann::json::parse(mistake.out);
  EXPECT_EQ(stateFindings(report["canvases"][0]),
            (std::vector<std::string>{"warning:reversed-z-without-zero-to-one",
                                      "error:reversed-z-mismatch", "warning:infinite-far-plane",
                                      "error:clear-depth-mismatch"}));
  const nlohmann::json& depth = report["canvases"][0]["check"]["groups"][0]["depth_state"];
  EXPECT_EQ(depth["clip_depth"], "negative-one-to-one");
  EXPECT_EQ(depth["depth_func"], "GL_LEQUAL");
  EXPECT_EQ(report["canvases"][0]["check"]["groups"][0]["properties"]["built_for"], "zo-reversed");

  const auto reversed =
      runClipray("check --page '" + threePage("orthographic-reversed.html") + "'", folder.path());
  // The reversed orthographic camera as three.js builds it: right-handed, looking down -z, its
  // near plane 0.1 in front of the camera (a reading along where reversed depth grows would turn
  // all three around and warn that culling keeps the insides).
  EXPECT_EQ(reversed.status, 0) << reversed.err;
  EXPECT_NE(reversed.out.find("  matrix: orthographic, right-handed, reversed-Z\n"
                              "    looking along (0, 0, -1)\n"
                              "    near plane at 0.1 +-0.00019, far 100 +-0.00019 from the world "
                              "origin"),
            std::string::npos)
      << reversed.out;
  EXPECT_NE(reversed.out.find("0 errors, 0 warnings, 0 notes"), std::string::npos) << reversed.out;
}

// Bad input: one line naming the value, exit 2, nothing written.
void expectBadInput(const std::string& arguments, const std::string& line,
                    const std::string& environment = "") {
  TempFolder folder;
  const auto result = runClipray(arguments, folder.path(), environment);
  EXPECT_EQ(result.status, 2) << result.err;
  EXPECT_EQ(result.err, "clipray: " + line + "\n");
  EXPECT_EQ(result.out, "");
  EXPECT_EQ(std::distance(fs::directory_iterator(folder.path()), fs::directory_iterator()), 0);
}

TEST(PageReconcileCli, BadInputIsOneLineAndNothingWritten) {
  const std::string noThree = std::string(CLIPRAY_SOURCE_DIR) + "/tests/webgl/no.html";
  // A WebGL page without three.js: the picking skipped, the state check's counts given.
  expectBadInput("reconcile --page '" + noThree + "'",
                 noThree +
                     ": no three.js picking to reconcile (no three.js renderer was observed); "
                     "picking skipped; the state check found 0 errors, 0 warnings, 0 notes "
                     "(clipray check --page tells them)");
  const std::string neverDraws = std::string(CLIPRAY_SOURCE_DIR) + "/tests/webgl/never-draws.html";
  expectBadInput("reconcile --page '" + neverDraws + "' --timeout 2",
                 neverDraws + ": never drew in 2 s (1 WebGL context)");
  expectBadInput("reconcile --page ftp://example.com/page.html",
                 "ftp://example.com/page.html: not an http(s) or file URL (ftp:)");
  expectBadInput("reconcile --page missing.html", "missing.html: no such file");
  expectBadInput("reconcile --page '" + noThree + "' --grid 32",
                 "--grid: expected CxR with 1 to 4096 columns and rows (e.g. 32x24), got \"32\"");
  expectBadInput("reconcile --page '" + noThree + "' --frames 0",
                 "--frames: expected a number of frames from 1 to 100000 with --page, got 0");
  expectBadInput("reconcile --page '" + noThree + "' --conventions zo",
                 "--conventions: not with --page (the page draws itself)");
  expectBadInput("reconcile scenes/standard.json --page '" + noThree + "'",
                 "--page: the page is the scene; give no scene files (got scenes/standard.json)");
  expectBadInput("reconcile --grid 8x8", "--grid, --frames and --timeout need --page");
  expectBadInput("reconcile --no-toggle", "--no-toggle needs --page");
  expectBadInput("reconcile --page '" + threePage("perspective.html") + "'",
                 "chromium not found at /no/such/chromium (CLIPRAY_CHROMIUM): install Debian's "
                 "package chromium (harness/install-deps.sh does)",
                 "CLIPRAY_CHROMIUM=/no/such/chromium");
}

}  // namespace
}  // namespace clipray

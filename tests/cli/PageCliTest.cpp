// `clipray check --page` on the WebGL test pages (tests/webgl/), in Debian's chromium headless on
// SwiftShader (harness/install-deps.sh installs it): what each page's recorded calls read as, the
// exit statuses, and the one-line errors for pages and browsers that cannot be checked. Each
// page costs one browser start (a few seconds); the pages that never draw cost their --timeout.
// A browser that fails to start fails these tests with its stderr (in the error line), never
// skips them.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

namespace fs = std::filesystem;
using testing::runClipray;
using testing::TempFolder;

std::string page(const std::string& name) {
  return std::string(CLIPRAY_SOURCE_DIR) + "/tests/webgl/" + name;
}

std::vector<std::string> codes(const nlohmann::json& group) {
  std::vector<std::string> result;
  for (const auto& f : group["findings"]) {
    result.push_back(f["severity"].get<std::string>() + ":" + f["code"].get<std::string>());
  }
  return result;
}

// The one canvas of a test page and its one group (one program, one matrix, one depth state).
struct PageReading {
  int status = -1;
  nlohmann::json report, canvas, group;
};

PageReading checkPage(const std::string& name, const fs::path& folder,
                      const std::string& source = "uniform clipFromWorld (program 1)") {
  const auto result = runClipray("check --page '" + page(name) + "' --json", folder);
  PageReading reading;
  reading.status = result.status;
  EXPECT_TRUE(result.err.empty()) << result.err;
  if (result.status != 0 && result.status != 1) return reading;
  reading.report = nlohmann::json::parse(result.out);
  EXPECT_EQ(reading.report["tool"], "clipray check --page");
  EXPECT_EQ(reading.report["frames"], 3);  // --frames' default
  EXPECT_EQ(reading.report["draws"], 6);   // two triangles a frame
  EXPECT_EQ(reading.report["device_pixel_ratio"], 1.0);
  EXPECT_EQ(reading.report["canvases"].size(), 1u);
  reading.canvas = reading.report["canvases"][0];
  EXPECT_EQ(reading.canvas["name"], "canvas#view");
  EXPECT_EQ(reading.canvas["type"], "webgl2");
  EXPECT_EQ(reading.canvas["canvas"]["drawingBufferWidth"], 320);
  EXPECT_EQ(reading.canvas["canvas"]["drawingBufferHeight"], 240);
  const nlohmann::json& check = reading.canvas["check"];
  EXPECT_EQ(check["frames"]["read"], 3);
  EXPECT_EQ(check["draws_with_projection"], 6);
  EXPECT_EQ(check["groups"].size(), 1u);
  reading.group = check["groups"][0];
  EXPECT_EQ(reading.group["source"], source);
  EXPECT_EQ(reading.group["distinct_matrices"], 1);
  EXPECT_EQ(reading.group["draws"], 6);
  const nlohmann::json& depth = reading.group["depth_state"];
  EXPECT_EQ(depth["depth_test"], true);
  EXPECT_EQ(depth["depth_format"], "24");  // the drawing buffer's DEPTH_BITS
  EXPECT_EQ(depth["viewport"], nlohmann::json::array({320, 240}));
  EXPECT_EQ(depth["clip_origin"], "lower-left");
  return reading;
}

TEST(PageCli, CorrectNoPageChecksClean) {
  TempFolder folder;
  const PageReading r = checkPage("no.html", folder.path());
  ASSERT_EQ(r.status, 0);
  EXPECT_EQ(r.group["depth_state"]["clip_depth"], "negative-one-to-one");
  EXPECT_EQ(r.group["depth_state"]["depth_func"], "GL_LESS");
  EXPECT_EQ(r.group["depth_state"]["cleared_depth"], 1.0);
  EXPECT_EQ(r.group["properties"]["built_for"], "no");
  EXPECT_EQ(r.group["properties"]["reversed"], false);
  EXPECT_NEAR(r.group["properties"]["near"].get<double>(), 0.1, 2e-6);
  EXPECT_NEAR(r.group["properties"]["far"].get<double>(), 100.0, 0.02);
  EXPECT_NEAR(r.group["properties"]["fov_y_degrees"].get<double>(), 60.0, 1e-4);
  EXPECT_EQ(codes(r.group), std::vector<std::string>{});
  EXPECT_EQ(r.report["verdict"], "ok");
}

TEST(PageCli, CorrectReversedZPageChecksClean) {
  TempFolder folder;
  const PageReading r = checkPage("zo-reversed.html", folder.path());
  ASSERT_EQ(r.status, 0);
  // clipControlEXT(LOWER_LEFT_EXT, ZERO_TO_ONE_EXT), GREATER, clearDepth(0).
  EXPECT_EQ(r.group["depth_state"]["clip_depth"], "zero-to-one");
  EXPECT_EQ(r.group["depth_state"]["depth_func"], "GL_GREATER");
  EXPECT_EQ(r.group["depth_state"]["cleared_depth"], 0.0);
  EXPECT_EQ(r.group["properties"]["built_for"], "zo-reversed");
  EXPECT_EQ(r.group["properties"]["reversed"], true);
  EXPECT_NEAR(r.group["properties"]["near"].get<double>(), 0.1, 2e-6);
  EXPECT_NEAR(r.group["properties"]["far"].get<double>(), 100.0, 0.02);
  EXPECT_EQ(codes(r.group), std::vector<std::string>{});
  EXPECT_EQ(r.report["verdict"], "ok");
}

// The NO-under-ZO mistake's twin: a ZO projection under WebGL's default [-1, 1] clip depth.
TEST(PageCli, ZeroToOneProjectionWithoutClipControlIsAMismatch) {
  TempFolder folder;
  const PageReading r = checkPage("zo-without-clip-control.html", folder.path());
  ASSERT_EQ(r.status, 1);
  EXPECT_EQ(r.group["depth_state"]["clip_depth"], "negative-one-to-one");
  EXPECT_EQ(r.group["depth_state"]["calls"]["clip_control"], 0);
  EXPECT_EQ(r.group["properties"]["built_for"], "zo");
  // Under [-1, 1] the rasterizer keeps geometry down to z_ndc = -1, at 0.0500252: half the
  // intended near plane, 0.1.
  EXPECT_NEAR(r.group["properties"]["near"].get<double>(), 0.0500252, 2e-6);
  EXPECT_NEAR(r.group["properties"]["near_if_built_for_zo"].get<double>(), 0.1, 2e-6);
  EXPECT_EQ(codes(r.group), std::vector<std::string>{"error:depth-convention-mismatch"});
  EXPECT_EQ(r.report["verdict"], "errors");
}

TEST(PageCli, ReversedProjectionWithLessIsAMismatchInTextToo) {
  TempFolder folder;
  const PageReading r = checkPage("reversed-less.html", folder.path());
  ASSERT_EQ(r.status, 1);
  EXPECT_EQ(r.group["depth_state"]["clip_depth"], "zero-to-one");
  EXPECT_EQ(r.group["depth_state"]["depth_func"], "GL_LESS");
  EXPECT_EQ(r.group["depth_state"]["cleared_depth"], 1.0);
  EXPECT_EQ(r.group["properties"]["reversed"], true);
  EXPECT_EQ(codes(r.group),
            (std::vector<std::string>{"error:reversed-z-mismatch", "error:clear-depth-mismatch"}));

  // The text report: the page, the canvas, then the trace checker's report of its calls.
  const auto text = runClipray("check --page '" + page("reversed-less.html") + "'", folder.path());
  EXPECT_EQ(text.status, 1) << text.err;
  EXPECT_EQ(text.out.rfind("page " + page("reversed-less.html") +
                               ": 3 frames, 6 draws on 1 canvas\n\ncanvas#view (webgl2): drawing "
                               "buffer 320x240, canvas 320x240, shown at 320x240 CSS px, "
                               "devicePixelRatio 1, depth buffer 24 bits; ",
                           0),
            0u)
      << text.out;
  for (const char* line :
       {"  calls read as a trace: 3 frames, 6 draws (6 with a projection), 1 distinct (matrix, "
        "depth state) pairs in 1 groups\n",
        "  depth state: clip control lower-left, zero-to-one; depth test GL_LESS; depth range 0, "
        "1; cleared to 1; viewport 320x240; depth buffer 24\n",
        "  error [reversed-z-mismatch] the matrix is reversed-Z (near maps to 1, far to 0) but the "
        "app declares a classic depth test: with GL_LESS and clear 1 the farthest surface wins",
        "\n2 errors, 0 warnings, 0 notes\n"}) {
    EXPECT_NE(text.out.find(line), std::string::npos) << line << "\n---\n" << text.out;
  }
}

// The classic NO-under-ZO mistake with the camera in a std140 uniform block: the matrix is read
// from the bytes bufferSubData wrote (exact float32, not 7-digit decimals).
TEST(PageCli, UniformBlockMatrixUnderClipControlIsAMismatch) {
  TempFolder folder;
  const PageReading r =
      checkPage("ubo-no-under-zo.html", folder.path(), "ubo Camera.clipFromWorld (program 1)");
  ASSERT_EQ(r.status, 1);
  EXPECT_EQ(r.group["depth_state"]["clip_depth"], "zero-to-one");
  EXPECT_EQ(r.group["properties"]["built_for"], "no");
  EXPECT_EQ(r.group["properties"]["precision"], "float32");
  // Under [0, 1] the rasterizer clips at z_ndc = 0: the near plane moves to 0.1998.
  EXPECT_NEAR(r.group["properties"]["near"].get<double>(), 0.1998, 2e-6);
  EXPECT_NEAR(r.group["properties"]["near_if_built_for_no"].get<double>(), 0.1, 2e-6);
  EXPECT_EQ(codes(r.group), std::vector<std::string>{"error:depth-convention-mismatch"});
}

// Several canvases: each named (its id, else its order) and checked on its own; a WebGL 1
// context is recorded as a WebGL 2 one is.
TEST(PageCli, EachCanvasIsCheckedOnItsOwnWebGl1Included) {
  TempFolder folder;
  const auto result =
      runClipray("check --page '" + page("two-canvases.html") + "' --json", folder.path());
  ASSERT_EQ(result.status, 1) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["draws"], 12);
  ASSERT_EQ(report["canvases"].size(), 2u);
  const nlohmann::json& main = report["canvases"][0];
  EXPECT_EQ(main["name"], "canvas#main");
  EXPECT_EQ(main["type"], "webgl2");
  EXPECT_EQ(main["check"]["verdict"], "ok");
  const nlohmann::json& mainGroup = main["check"]["groups"][0];
  EXPECT_EQ(mainGroup["source"], "uniform clipFromWorld (program 1)");
  EXPECT_EQ(mainGroup["properties"]["built_for"], "zo-reversed");
  EXPECT_EQ(codes(mainGroup), std::vector<std::string>{});

  const nlohmann::json& second = report["canvases"][1];
  EXPECT_EQ(second["name"], "canvas 2");
  EXPECT_EQ(second["type"], "webgl");
  EXPECT_EQ(second["canvas"]["drawingBufferWidth"], 160);
  EXPECT_EQ(second["check"]["verdict"], "errors");
  const nlohmann::json& secondGroup = second["check"]["groups"][0];
  EXPECT_EQ(secondGroup["source"], "uniform clipFromWorld (program 2)");
  EXPECT_EQ(secondGroup["depth_state"]["viewport"], nlohmann::json::array({160, 120}));
  EXPECT_EQ(codes(secondGroup), std::vector<std::string>{"error:depth-convention-mismatch"});
  EXPECT_EQ(report["verdict"], "errors");
}

// --verify: the page's own depth buffer after the last frame (blitted into a depth texture,
// drawn through texelFetch into R32F, read as RGBA/FLOAT) set against the matrix. The ZO matrix
// drawn under [-1, 1] puts the surfaces at view depths 4.1 to 8; a pick that unprojects those
// depths as ZO lands at 7.9 to 14.8, up to 92% off. A WebGL 1 canvas is not verified, and says so.
TEST(PageCli, VerifyReadsThePagesDepthBuffer) {
  TempFolder folder;
  const auto result = runClipray(
      "check --page '" + page("zo-without-clip-control.html") + "' --verify --json", folder.path());
  ASSERT_EQ(result.status, 1) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  const nlohmann::json& verify = report["canvases"][0]["check"]["groups"][0]["verify"];
  EXPECT_EQ(verify["frame"], 2);
  EXPECT_EQ(verify["pixels"], 320 * 240);
  EXPECT_EQ(verify["written"], 13562);  // both triangles' pixels (SwiftShader's rasterization)
  EXPECT_NEAR(verify["min_depth"].get<double>(), 0.98829, 1e-5);
  EXPECT_NEAR(verify["max_depth"].get<double>(), 0.994226, 1e-5);
  EXPECT_NEAR(verify["nearest_view_depth"].get<double>(), 4.09888, 1e-3);
  EXPECT_NEAR(verify["farthest_view_depth"].get<double>(), 7.97691, 2e-3);
  EXPECT_NEAR(verify["picked_nearest"].get<double>(), 7.87498, 2e-3);
  EXPECT_NEAR(verify["picked_farthest"].get<double>(), 14.7752, 4e-3);
  EXPECT_NEAR(verify["pick_worst_relative_error"].get<double>(), 0.921253, 1e-3);
  EXPECT_EQ(verify["observations"][0],
            "depth buffer after call 31 (frame 2): 320x240 GL_DEPTH24_STENCIL8, 13562 of 76800 "
            "pixels differ from the cleared depth 1");

  const auto two =
      runClipray("check --page '" + page("two-canvases.html") + "' --verify", folder.path());
  ASSERT_EQ(two.status, 1) << two.err;
  for (const char* line :
       {"  verify (the page's depth buffer after the last frame):\n    depth buffer after call 56 "
        "(frame 2): 320x240 GL_DEPTH24_STENCIL8, 13562 of 76800 pixels differ from the cleared "
        "depth 0\n    window depth used: 0.0115479 to 0.0234204\n",
        "  verify (the page's depth buffer after the last frame):\n    not verified: a WebGL 1 "
        "context (reading depth needs WebGL 2)\n"}) {
    EXPECT_NE(two.out.find(line), std::string::npos) << line << "\n---\n" << two.out;
  }
}

// Bad input: one line naming the value, exit 2, nothing on stdout.
void expectBadInput(const std::string& arguments, const std::string& line,
                    const std::string& environment = "") {
  TempFolder folder;
  const auto result = runClipray(arguments, folder.path(), environment);
  EXPECT_EQ(result.status, 2) << result.err;
  EXPECT_EQ(result.err, "clipray: " + line + "\n");
  EXPECT_EQ(result.out, "");
  EXPECT_EQ(std::distance(fs::directory_iterator(folder.path()), fs::directory_iterator()), 0);
}

TEST(PageCli, TargetsThatAreNoPageAreRefusedBeforeTheBrowserStarts) {
  expectBadInput("check --page ftp://example.com/page.html",
                 "ftp://example.com/page.html: not an http(s) or file URL (ftp:)");
  expectBadInput("check --page 'javascript:alert(1)'",
                 "javascript:alert(1): not an http(s) or file URL (javascript:)");
  expectBadInput("check --page missing.html", "missing.html: no such file");
  expectBadInput("check --page file:///no/such/page.html",
                 "file:///no/such/page.html: no such file");
  expectBadInput("check --page '" + page("no.html") + "' --frames 0",
                 "--frames: expected a number of frames from 1 to 100000 with --page, got '0'");
  expectBadInput("check --timeout 5", "--timeout needs --page");
}

TEST(PageCli, MissingChromiumNamesTheDebianPackage) {
  expectBadInput("check --page '" + page("no.html") + "'",
                 "chromium not found at /no/such/chromium (CLIPRAY_CHROMIUM): install Debian's "
                 "package chromium (harness/install-deps.sh does)",
                 "CLIPRAY_CHROMIUM=/no/such/chromium");
}

TEST(PageCli, ABrowserThatDiesSaysWhatItWrote) {
  TempFolder scripts;
  const fs::path fake = scripts.path() / "chromium";
  std::ofstream(fake) << "#!/bin/sh\necho 'cannot open display' >&2\nexit 3\n";
  fs::permissions(fake, fs::perms::owner_all);
  expectBadInput("check --page '" + page("no.html") + "'",
                 "chromium closed the DevTools pipe (exit status 3); its stderr ends:\n"
                 "cannot open display",
                 "CLIPRAY_CHROMIUM='" + fake.string() + "'");
}

// Chromium refuses the discard port (net/base/port_util.cc's restricted ports) without any
// network: the page's navigation fails, and its errorText is the reason given.
TEST(PageCli, APageThatDoesNotLoadSaysWhy) {
  expectBadInput("check --page http://127.0.0.1:9/page.html",
                 "http://127.0.0.1:9/page.html: does not load (net::ERR_UNSAFE_PORT)");
}

TEST(PageCli, PagesWithoutWebGlOrDrawsEndAtTheTimeout) {
  expectBadInput("check --page '" + page("no-webgl.html") + "' --timeout 2",
                 page("no-webgl.html") + ": no WebGL context after 2 s");
  expectBadInput("check --page '" + page("never-draws.html") + "' --timeout 2",
                 page("never-draws.html") + ": never drew in 2 s (1 WebGL context)");
  // The page's own first uncaught error, where it threw one.
  expectBadInput("check --page '" + page("throws.html") + "' --timeout 2",
                 page("throws.html") +
                     ": never drew in 2 s (1 WebGL context); the page threw: Uncaught Error: "
                     "scene failed to load");
}

}  // namespace
}  // namespace clipray

// `clipray check --capture` on RenderDoc captures of the trace-test apps
// (tests/traceapps/ConventionApp.cpp), captured at test time through RenderDoc's in-app API
// (librenderdoc.so preloaded, CLIPRAY_CAPTURE_RDC naming the file) on Mesa's surfaceless EGL
// platform, and replayed by the capture reader (harness/renderdoc/) with python3-renderdoc. Each
// case is also recorded with apitrace and checked with --trace: the capture must read as its trace
// does (one state model, two readers). Needs Debian's renderdoc, python3-renderdoc,
// librenderdoc-dev and apitrace (harness/install-deps.sh); without them the tests fail with the
// tools' own output.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "capture/CaptureApps.hpp"
#include "clipray/trace/CaptureGeometry.hpp"
#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::captureCase;
using testing::runClipray;
using testing::runIn;
using testing::runReplayIn;
using testing::TempFolder;

std::string traceCase(const std::string& name, const TempFolder& folder) {
  return runIn(
      folder,
      "apitrace trace --api egl -o '" + name + ".trace' '" + CLIPRAY_TRACE_APP + "' " + name + " 1",
      "apitrace trace of " + name);
}

struct Checked {
  int status = -1;
  nlohmann::json report;
  std::string err;
};

Checked check(const std::string& arguments, const TempFolder& folder) {
  Checked checked;
  const auto result = runClipray("check " + arguments + " --json", folder.path());
  checked.status = result.status;
  checked.err = result.err;
  if (result.status == 0 || result.status == 1) checked.report = nlohmann::json::parse(result.out);
  return checked;
}

std::vector<std::string> codes(const nlohmann::json& group) {
  std::vector<std::string> result;
  for (const auto& f : group["findings"]) {
    result.push_back(f["severity"].get<std::string>() + ":" + f["code"].get<std::string>());
  }
  return result;
}

// "uniform clipFromWorld (Program 29)" -> "uniform clipFromWorld": the program's name is each
// reader's own (RenderDoc's resource name, the trace's GL name).
std::string sourceKind(const nlohmann::json& group) {
  const std::string source = group["source"];
  return source.substr(0, source.find(" ("));
}

struct Case {
  std::string name;
  int status = 0;
  std::vector<std::string> codes;
  std::string builtFor;
};

void PrintTo(const Case& c, std::ostream* out) {
  *out << c.name;
}

class CaptureCase : public ::testing::TestWithParam<Case> {};

// The capture's one group reads as the trace's: the same findings, reading and depth state (the
// calls aside: event IDs there, call numbers here).
TEST_P(CaptureCase, ReadsAsItsTrace) {
  const Case& expected = GetParam();
  TempFolder folder;
  ASSERT_EQ(captureCase(expected.name, folder), "");
  const Checked captured = check("--capture " + expected.name + ".rdc", folder);
  ASSERT_EQ(captured.status, expected.status) << captured.err;
  ASSERT_EQ(traceCase(expected.name, folder), "");
  const Checked traced = check("--trace " + expected.name + ".trace", folder);
  ASSERT_EQ(traced.status, expected.status) << traced.err;
  ASSERT_EQ(captured.report["groups"].size(), 1u) << captured.report.dump(2);
  ASSERT_EQ(traced.report["groups"].size(), 1u) << traced.report.dump(2);
  const nlohmann::json& group = captured.report["groups"][0];
  const nlohmann::json& twin = traced.report["groups"][0];
  EXPECT_EQ(codes(group), expected.codes);
  EXPECT_EQ(codes(twin), expected.codes);
  EXPECT_EQ(group["properties"]["built_for"], expected.builtFor);
  EXPECT_EQ(twin["properties"]["built_for"], expected.builtFor);
  EXPECT_EQ(sourceKind(group), sourceKind(twin));
  nlohmann::json state = group["depth_state"], traceState = twin["depth_state"];
  state.erase("calls");
  traceState.erase("calls");
  EXPECT_EQ(state, traceState);
  EXPECT_EQ(group["draws"], 1);
  EXPECT_EQ(captured.report["tool"], "clipray check --capture");
  EXPECT_EQ(captured.report["capture"]["api"], "OpenGL");
  EXPECT_EQ(captured.report["capture"]["draws_in_capture"], 1);
  ASSERT_EQ(captured.report["draw_list"].size(), 1u);
  const nlohmann::json& draw = captured.report["draw_list"][0];
  EXPECT_EQ(draw["event"], group["first"]["call"]);
  EXPECT_EQ(draw["name"], "glDrawArrays()");
  EXPECT_EQ(draw["depth_write"], true);
  EXPECT_EQ(draw["polygon_offset"],
            (nlohmann::json{{"factor", 0.0}, {"units", 0.0}, {"clamp", 0.0}}));
  EXPECT_NE(draw["shaders"]["vertex"].get<std::string>().find("clipFromWorld"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(
    Apps, CaptureCase,
    ::testing::Values(Case{"no", 0, {}, "no"}, Case{"zo", 0, {}, "zo"},
                      Case{"zo-depth-texture", 0, {}, "zo"},
                      Case{"reversed-infinite", 0, {"warning:infinite-far-plane"}, "zo-reversed"},
                      Case{"no-under-zo", 1, {"error:depth-convention-mismatch"}, "no"},
                      Case{"reversed-with-less",
                           1,
                           {"error:reversed-z-mismatch", "warning:infinite-far-plane",
                            "error:clear-depth-mismatch"},
                           "zo-reversed"},
                      Case{"row-major-untransposed", 1, {"error:likely-transposed"}, "zo-reversed"},
                      Case{"vulkan-flip", 0, {"warning:y-flipped"}, "zo"},
                      Case{"d3d-style-culled", 0, {"info:y-flipped"}, "zo"},
                      Case{"d3d-style-culled-ccw",
                           0,
                           {"info:y-flipped", "warning:face-culling-keeps-insides"},
                           "zo"},
                      Case{"zo-depth-clamp", 0, {"info:depth-clamp-near-plane"}, "zo"},
                      Case{"zo-ubo", 0, {}, "zo"},
                      Case{"no-under-zo-ubo", 1, {"error:depth-convention-mismatch"}, "no"},
                      Case{"no-under-zo-pipeline", 1, {"error:depth-convention-mismatch"}, "no"}),
    [](const ::testing::TestParamInfo<Case>& param) {
      std::string name = param.param.name;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// --verify reads the depth attachment as the group's first draw leaves it, replayed by RenderDoc,
// and says of it what --trace --verify says of apitrace's replay: the same pixels and depths (one
// llvmpipe rasterizes both), the same view depths and misread picks. The float32 and 24-bit
// attachments, and a reversed matrix drawn with GL_LESS.
TEST(CaptureCli, VerifyReadsTheCapturedDepthAsTheTraceReplayDoes) {
  TempFolder folder;
  for (const std::string name : {"no-under-zo", "zo-depth-texture", "reversed-with-less"}) {
    ASSERT_EQ(captureCase(name, folder), "");
    ASSERT_EQ(traceCase(name, folder), "");
    const Checked captured = check("--capture " + name + ".rdc --verify", folder);
    const Checked traced = check("--trace " + name + ".trace --verify", folder);
    ASSERT_EQ(captured.status, traced.status) << name << captured.err << traced.err;
    nlohmann::json verify = captured.report["groups"][0]["verify"];
    nlohmann::json replayed = traced.report["groups"][0]["verify"];
    ASSERT_TRUE(verify.contains("written")) << name << verify.dump(2);
    EXPECT_GT(verify["written"].get<int>(), 0) << name;
    EXPECT_EQ(verify["call"], captured.report["groups"][0]["first"]["call"]) << name;
    // The first line names the call (an event ID here) and the format as each reader does.
    const std::string head = verify["observations"][0];
    EXPECT_TRUE(head.starts_with("depth buffer after call " + verify["call"].dump() +
                                 " (frame 0): 64x48 depth format "))
        << head;
    // The depths are the same bits; the view depths come through each reader's copy of the
    // matrix (RenderDoc's uniform contents, apitrace's decimal dump), which differ in the last
    // float32 place, amplified here by the projection's conditioning near the far end of the
    // depth range: up to 6e-6 relative measured, bounded at 1e-5.
    for (const char* key : {"written", "pixels", "frame", "min_depth", "max_depth"}) {
      EXPECT_EQ(verify[key], replayed[key]) << name << " " << key;
    }
    EXPECT_EQ(verify["observations"][1], replayed["observations"][1]) << name;
    for (const char* key : {"nearest_view_depth", "farthest_view_depth", "picked_nearest",
                            "picked_farthest", "pick_worst_relative_error"}) {
      ASSERT_EQ(verify[key].is_null(), replayed[key].is_null()) << name << " " << key;
      if (verify[key].is_null()) continue;
      const double a = verify[key], b = replayed[key];
      EXPECT_LE(std::abs(a - b), 1e-5 * std::abs(b)) << name << " " << key;
    }
  }
  const auto text = runClipray("check --capture no-under-zo.rdc --verify", folder.path());
  EXPECT_NE(text.out.find("  verify (replayed by RenderDoc):\n    depth buffer after call 17 "
                          "(frame 0): 64x48 depth format 32f, 56 of 3072 pixels differ from the "
                          "cleared depth 1\n"),
            std::string::npos)
      << text.out;
}

// The reader's --geometry (groundwork for reconcile --capture): the draw's gl_Position per vertex
// as RenderDoc's post-VS data holds it, which for the test app is the uploaded matrix (the draw
// line's rows) times each vertex of its triangle at world z = 0, computed in float by the shader:
// within 4 float32 roundings of the largest term.
TEST(CaptureCli, GeometryHoldsTheVertexShadersClipPositions) {
  TempFolder folder;
  ASSERT_EQ(captureCase("zo", folder), "");
  const std::string reader =
      (std::filesystem::path(CLIPRAY_BINARY).parent_path() / "clipray-capture-reader.py").string();
  ASSERT_EQ(
      runReplayIn(folder, "(/usr/bin/python3 '" + reader + "' zo.rdc >draws.jsonl)", "the reader"),
      "");
  ASSERT_EQ(
      runReplayIn(folder, "(/usr/bin/python3 '" + reader + "' zo.rdc --geometry >geometry.jsonl)",
                  "the reader's --geometry"),
      "");
  std::vector<nlohmann::json> draws, geometry;
  for (const auto& [file, lines] :
       {std::pair{"draws.jsonl", &draws}, {"geometry.jsonl", &geometry}}) {
    std::istringstream text(testing::readText(folder.path() / file));
    for (std::string line; std::getline(text, line);) {
      if (line.starts_with("{")) lines->push_back(nlohmann::json::parse(line));
    }
  }
  ASSERT_EQ(draws.size(), 2u);  // the capture line and the one draw
  ASSERT_EQ(geometry.size(), 2u);
  const trace::CapturedDrawGeometry drawn = trace::capturedDrawGeometry(geometry[1]);
  EXPECT_EQ(drawn.event, draws[1]["event"].get<std::uint64_t>());
  ASSERT_EQ(drawn.clip.size(), 3u);
  const nlohmann::json& rows = draws[1]["matrices"][0]["rows"];
  const glm::dvec3 triangle[3] = {{-1, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int v = 0; v < 3; ++v) {
    for (int r = 0; r < 4; ++r) {
      double exact = rows[r][3].get<double>(), largest = std::abs(exact);
      for (int c = 0; c < 3; ++c) {
        exact += rows[r][c].get<double>() * triangle[v][c];
        largest = std::max(largest, std::abs(rows[r][c].get<double>() * triangle[v][c]));
      }
      EXPECT_NEAR(drawn.clip[static_cast<std::size_t>(v)][r], exact, 4 * 0x1p-24 * largest)
          << "vertex " << v << " row " << r;
    }
  }
}

// The event IDs the findings cite are the capture's own: the reversed-Z mismatch names the
// glDepthFunc event, the clear-depth mismatch the glClear event.
TEST(CaptureCli, FindingsCiteEventIds) {
  TempFolder folder;
  ASSERT_EQ(captureCase("reversed-with-less", folder), "");
  const Checked captured = check("--capture reversed-with-less.rdc", folder);
  ASSERT_EQ(captured.status, 1) << captured.err;
  const nlohmann::json& group = captured.report["groups"][0];
  EXPECT_EQ(group["depth_state"]["calls"]["depth_func"], 8);
  EXPECT_EQ(group["depth_state"]["calls"]["clear"], 15);
  EXPECT_EQ(group["findings"][2]["message"],
            "the depth buffer is cleared to 1 (call 15), the far value of the classic "
            "convention; this matrix puts far at 0, so the cleared depth is nearer than any "
            "surface and nothing passes the test");
  const auto text = runClipray("check --capture reversed-with-less.rdc --draws 17", folder.path());
  EXPECT_EQ(text.status, 1) << text.err;
  EXPECT_TRUE(text.out.starts_with("capture reversed-with-less.rdc: ")) << text.out;
  EXPECT_NE(text.out.find("calls are RenderDoc event IDs (EIDs)\n  draw 17 glDrawArrays(): "
                          "Program 29, depth writes on\n"),
            std::string::npos)
      << text.out;
}

void expectRefused(const std::string& arguments, const TempFolder& folder,
                   const std::string& message, const std::string& environment = "") {
  std::vector<std::filesystem::path> before;
  for (const auto& entry : std::filesystem::directory_iterator(folder.path())) {
    before.push_back(entry.path());
  }
  const auto result = runClipray("check " + arguments, folder.path(), environment);
  EXPECT_EQ(result.status, 2) << arguments;
  EXPECT_EQ(result.out, "") << arguments;
  EXPECT_EQ(result.err, "clipray: " + message + "\n") << arguments;
  std::vector<std::filesystem::path> after;
  for (const auto& entry : std::filesystem::directory_iterator(folder.path())) {
    after.push_back(entry.path());
  }
  std::sort(before.begin(), before.end());
  std::sort(after.begin(), after.end());
  EXPECT_EQ(before, after) << arguments;
}

TEST(CaptureCli, BadCaptures) {
  TempFolder folder;
  ASSERT_EQ(captureCase("zo", folder), "");
  ASSERT_EQ(captureCase("identity", folder), "");
  ASSERT_EQ(captureCase("clear-only", folder), "");
  {
    std::ifstream whole(folder.path() / "zo.rdc", std::ios::binary);
    std::string bytes(2000, '\0');
    whole.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    std::ofstream(folder.path() / "truncated.rdc", std::ios::binary) << bytes;
    // No Vulkan or D3D device here to capture from: the zo capture's header claims another API.
    // RenderDoc's file starts with the thumbnail, then the capture's metadata: the driver's ID
    // (uint32; RDCDriver: OpenGL 2, D3D11 1, Vulkan 8) and its name (a length byte, the name
    // with its NUL). The reader must refuse from the header alone, before any replay.
    std::ifstream again(folder.path() / "zo.rdc", std::ios::binary);
    const std::string capture((std::istreambuf_iterator<char>(again)),
                              std::istreambuf_iterator<char>());
    const std::size_t name = capture.find(std::string("\x07OpenGL\0", 8));
    ASSERT_NE(name, std::string::npos);
    ASSERT_GE(name, 4u);
    for (const auto& [api, id] : {std::pair<std::string, char>{"Vulkan", 8}, {"D3D11", 1}}) {
      std::string other = capture;
      other.replace(name - 4, 4, std::string{id, 0, 0, 0});
      other.replace(name + 1, 7, (api + std::string(7, '\0')).substr(0, 7));
      std::ofstream(folder.path() / (api + ".rdc"), std::ios::binary) << other;
    }
    std::ofstream(folder.path() / "scene.json") << R"({"objects": []})";
    // Python without its site packages: no python3-renderdoc.
    std::ofstream(folder.path() / "bare-python") << "#!/bin/sh\nexec /usr/bin/python3 -S \"$@\"\n";
    std::filesystem::permissions(folder.path() / "bare-python", std::filesystem::perms::owner_all);
  }
  expectRefused("--capture missing.rdc", folder, "missing.rdc: cannot open file");
  expectRefused("--capture scene.json", folder,
                "scene.json: not a RenderDoc capture (RenderDoc: File I/O failed: I/O error "
                "reading magic number)");
  expectRefused("--capture truncated.rdc", folder,
                "truncated.rdc: a truncated or corrupted capture (RenderDoc: File is corrupted: "
                "Error seeking past binary section 'renderdoc/internal/framecapture' data)");
  expectRefused("--capture Vulkan.rdc", folder,
                "Vulkan.rdc: a Vulkan capture: clipray checks OpenGL and OpenGL ES captures only");
  expectRefused("--capture D3D11.rdc", folder,
                "D3D11.rdc: a D3D11 capture: clipray checks OpenGL and OpenGL ES captures only");
  expectRefused("--capture clear-only.rdc", folder, "clear-only.rdc: no draws in the capture");
  expectRefused("--capture identity.rdc", folder,
                "identity.rdc: none of the 1 draws has a matrix with a projection's structure "
                "(uniform mat4, std140 uniform block mat4 or fixed-function GL_PROJECTION)");
  expectRefused("--capture zo.rdc --draws 40-50", folder,
                "zo.rdc: --draws 40-50: no draw in that range (the capture's 1 draws are events "
                "17-17)");
  expectRefused("--capture zo.rdc --draws 9-1", folder,
                "--draws: expected A-B or A (RenderDoc event IDs, A <= B), got \"9-1\"");
  expectRefused("--draws 1-2", folder, "--draws needs --capture");
  expectRefused("--capture zo.rdc --frames 0", folder,
                "--frames needs --trace (--capture takes --draws)");
  expectRefused("--capture zo.rdc --declared-depth zo", folder,
                "--capture: the depth state and matrices come from the capture; give no check "
                "file, --trace or field options with it");
  expectRefused("--capture zo.rdc", folder,
                "RenderDoc's Python module is missing (No module named 'renderdoc'): install "
                "Debian's python3-renderdoc (harness/install-deps.sh)",
                "CLIPRAY_CAPTURE_PYTHON=./bare-python");
  expectRefused("--capture zo.rdc", folder,
                "/nonexistent/python3: cannot run Python for the capture reader: install Debian's "
                "python3 and python3-renderdoc (harness/install-deps.sh), or set "
                "CLIPRAY_CAPTURE_PYTHON",
                "CLIPRAY_CAPTURE_PYTHON=/nonexistent/python3");
}

// RenderDoc's replay now and then dies by a signal as it starts (runReader in
// CaptureFileCheck.cpp): a reader killed before its first line runs once more, and a second such
// death is reported with its status.
TEST(CaptureCli, ReaderKilledAsItStartsRunsOnceMore) {
  TempFolder folder;
  ASSERT_EQ(captureCase("zo", folder), "");
  // Stand-ins for Python, given the reader's path and arguments.
  std::ofstream(folder.path() / "crash-once")
      << "#!/bin/sh\nif [ ! -e crashed ]; then : > crashed; kill -SEGV $$; fi\n"
         "exec /usr/bin/python3 \"$@\"\n";
  std::ofstream(folder.path() / "crash-always") << "#!/bin/sh\nkill -SEGV $$\n";
  for (const char* name : {"crash-once", "crash-always"}) {
    std::filesystem::permissions(folder.path() / name, std::filesystem::perms::owner_all);
  }
  const auto once =
      runClipray("check --capture zo.rdc", folder.path(), "CLIPRAY_CAPTURE_PYTHON=./crash-once");
  EXPECT_EQ(once.status, 0) << once.err;
  EXPECT_TRUE(std::filesystem::exists(folder.path() / "crashed"));
  expectRefused("--capture zo.rdc", folder,
                "zo.rdc: the capture reader exited with status 139 (no output)",
                "CLIPRAY_CAPTURE_PYTHON=./crash-always");
}

// RenderDoc captures core-profile contexts only: the compatibility-profile app (the fixed-function
// case) gets no capture, and says so.
TEST(CaptureCli, CompatibilityProfileIsNotCaptured) {
  TempFolder folder;
  const std::string failure = captureCase("fixed-function-frustum-under-zo", folder);
  EXPECT_NE(failure.find("clipray_trace_app: RenderDoc captured nothing"), std::string::npos)
      << failure;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "fixed-function-frustum-under-zo.rdc"));
}

}  // namespace
}  // namespace clipray

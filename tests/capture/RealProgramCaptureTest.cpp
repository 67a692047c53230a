// `clipray check --capture` on frames of real, unmodified Debian programs: launched under Xvfb
// by `renderdoccmd capture` and captured through RenderDoc's target control
// (harness/renderdoc/clipray-capture-frame.py), replayed by the capture reader on llvmpipe.
// RenderDoc captures core-profile GL 3.2+ and GLES through EGL only, so the programs are the GLES 2
// ones: es2gears_x11 (mesa-utils-bin) and glmark2-es2 (glmark2-es2-x11); glxgears (legacy GL) is
// refused by RenderDoc, which the capture script reports. Needs xvfb-run, renderdoccmd and the
// programs (harness/install-deps.sh); the tests skip, naming what is missing, without them.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

// "" when every program is on PATH, else the first one missing.
std::string missingProgram(const std::vector<std::string>& programs) {
  for (const std::string& program : programs) {
    const std::string line = "command -v '" + program + "' >/dev/null 2>&1";
    if (std::system(line.c_str()) != 0) return program;
  }
  return "";
}

struct Captured {
  int status = -1;
  std::string output;
};

// FOLDER/OUT.rdc: one presented frame of PROGRAM under a 640x480 Xvfb screen, on llvmpipe. The
// display search starts at a number of this shell's own, so that tests run in parallel do not
// race for the same free display. The status is the capture script's own, written to a file
// inside xvfb-run: xvfb-run replaces it with 5 when its own clean-up fails ("problem while
// cleaning up temporary directory", seen once in CI after the script had exited 1).
Captured captureProgram(const std::string& out, const std::string& program,
                        const TempFolder& folder) {
  const std::filesystem::path log = folder.path() / ".capture.log";
  const std::filesystem::path status = folder.path() / ".capture.status";
  const std::string line = "cd '" + folder.path().string() +
                           "' && xvfb-run -a -n $((100 + $$ % 800)) -s '-screen 0 640x480x24' "
                           "env LIBGL_ALWAYS_SOFTWARE=1 sh -c '\"$@\"; echo $? >\"" +
                           status.string() +
                           "\"' sh /usr/bin/python3 '" CLIPRAY_CAPTURE_FRAME_SCRIPT "' '" + out +
                           "' --timeout 15 -- " + program + " >'" + log.string() + "' 2>&1";
  Captured captured;
  // xvfb-run -a can lose a race for a free display to another test's Xvfb starting at the same
  // moment ("Xvfb failed to start"): then it is asked again, a few times.
  for (int attempt = 0; attempt < 3; ++attempt) {
    std::filesystem::remove(status);
    const int raw = std::system(line.c_str());
    captured.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    captured.output = testing::readText(log);
    if (std::filesystem::exists(status)) captured.status = std::stoi(testing::readText(status));
    if (captured.output.find("Xvfb failed to start") == std::string::npos) break;
  }
  return captured;
}

nlohmann::json checkJson(const std::string& arguments, const TempFolder& folder, int status) {
  const auto result = runClipray("check " + arguments + " --json", folder.path());
  EXPECT_EQ(result.status, status) << result.err;
  if (result.status != 0 && result.status != 1) return nlohmann::json::object();
  return nlohmann::json::parse(result.out);
}

std::vector<std::string> codes(const nlohmann::json& findings) {
  std::vector<std::string> result;
  for (const auto& f : findings) {
    result.push_back(f["severity"].get<std::string>() + ":" + f["code"].get<std::string>());
  }
  return result;
}

#define SKIP_WITHOUT(...)                                                                   \
  do {                                                                                      \
    const std::string missing = missingProgram({"xvfb-run", "renderdoccmd", __VA_ARGS__});  \
    if (!missing.empty()) {                                                                 \
      GTEST_SKIP() << missing << " is not installed (harness/install-deps.sh installs it)"; \
    }                                                                                       \
  } while (false)

// es2gears (mesa-demos' GLES 2 gears, a 300x300 window): three gears, each drawn with its own
// model-view-projection from frustum(-1, 1, -h, h, 5, 60), h = 1 (a square window). No error; the
// note that the matrix changes between draws is true (per-object MVPs).
TEST(RealProgramCapture, Es2gearsChecksWithoutFalseFindings) {
  SKIP_WITHOUT("es2gears_x11");
  TempFolder folder;
  const Captured captured = captureProgram("es2gears.rdc", "es2gears_x11", folder);
  ASSERT_EQ(captured.status, 0) << captured.output;
  const nlohmann::json report = checkJson("--capture es2gears.rdc --verify", folder, 0);
  ASSERT_EQ(report["groups"].size(), 1u) << report.dump(2);
  EXPECT_EQ(report["capture"]["api"], "OpenGLES");
  EXPECT_EQ(report["capture"]["draws_in_capture"], 3);
  EXPECT_EQ(report["verdict"], "ok");
  EXPECT_EQ(codes(report["findings"]),
            std::vector<std::string>{"info:projection-changes-within-frame"});
  const nlohmann::json& group = report["groups"][0];
  EXPECT_EQ(codes(group["findings"]), std::vector<std::string>{});
  EXPECT_EQ(group["source"], "uniform ModelViewProjectionMatrix (Program 28)");
  EXPECT_EQ(group["draws"], 3);
  const nlohmann::json& properties = group["properties"];
  EXPECT_EQ(properties["built_for"], "no");
  EXPECT_EQ(properties["projection"], "perspective");
  EXPECT_NEAR(properties["near"].get<double>(), 5.0, 1e-4);
  EXPECT_NEAR(properties["far"].get<double>(), 60.0, 1e-3);
  EXPECT_NEAR(properties["fov_y_degrees"].get<double>(), 22.619865, 1e-4);  // 2 atan(1/5)
  const nlohmann::json& state = group["depth_state"];
  EXPECT_EQ(state["clip_depth"], "negative-one-to-one");
  EXPECT_EQ(state["depth_func"], "GL_LESS");
  EXPECT_EQ(state["depth_format"], "16");
  EXPECT_EQ(state["viewport"], nlohmann::json::array({300, 300}));
  EXPECT_EQ(state["cull_face"], "GL_BACK");
  // RenderDoc 1.24's GetTextureData gives zeros for a GLES D16 depth buffer; the reader's check
  // against PickPixel catches it and --verify notes it instead of reading wrong depths.
  const std::string failure = group["verify"].value("failure", "");
  EXPECT_EQ(failure.rfind("the decoded depth 0 at texel (150, 150) is not RenderDoc's ", 0), 0u)
      << failure;
  // reconcile --capture needs that depth: it refuses the frame, saying why, and writes nothing.
  const auto reconciled = runClipray("reconcile --capture es2gears.rdc --out out", folder.path());
  EXPECT_EQ(reconciled.status, 2);
  EXPECT_NE(
      reconciled.err.find(": the decoded depth 0 at texel (150, 150) is not RenderDoc's 0.95"),
      std::string::npos)
      << reconciled.err;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out"));
}

// glmark2-es2's build scene (the horse model, 160x120): perspective(fovy, aspect, 2, 2 + d) with
// d the model's diameter and fovy = 2 atan(r / (2 + r)), r = d / 2 (glmark2's scene-build.cpp);
// glDepthFunc(GL_LEQUAL) from its canvas. No finding; its 32f depth read back and used.
TEST(RealProgramCapture, Glmark2Es2BuildChecksWithoutFindings) {
  SKIP_WITHOUT("glmark2-es2");
  TempFolder folder;
  const Captured captured = captureProgram(
      "glmark2.rdc", "glmark2-es2 -s 160x120 -b build:use-vbo=true:duration=30", folder);
  ASSERT_EQ(captured.status, 0) << captured.output;
  const nlohmann::json report = checkJson("--capture glmark2.rdc --verify", folder, 0);
  ASSERT_EQ(report["groups"].size(), 1u) << report.dump(2);
  EXPECT_EQ(report["capture"]["api"], "OpenGLES");
  EXPECT_EQ(report["capture"]["draws_in_capture"], 1);
  EXPECT_EQ(report["verdict"], "ok");
  EXPECT_EQ(codes(report["findings"]), std::vector<std::string>{});
  const nlohmann::json& group = report["groups"][0];
  EXPECT_EQ(codes(group["findings"]), std::vector<std::string>{});
  EXPECT_EQ(group["source"], "uniform ModelViewProjectionMatrix (Program 46)");
  const nlohmann::json& properties = group["properties"];
  EXPECT_EQ(properties["built_for"], "no");
  EXPECT_NEAR(properties["near"].get<double>(), 2.0, 1e-4);
  const double far = properties["far"].get<double>();
  EXPECT_NEAR(far, 4.25224, 1e-4);
  const double radius = (far - 2.0) / 2.0;
  EXPECT_NEAR(properties["fov_y_degrees"].get<double>(),
              2.0 * std::atan(radius / (2.0 + radius)) * 180.0 / M_PI, 1e-4);
  const nlohmann::json& state = group["depth_state"];
  EXPECT_EQ(state["depth_func"], "GL_LEQUAL");
  EXPECT_EQ(state["depth_format"], "32f");
  EXPECT_EQ(state["viewport"], nlohmann::json::array({160, 120}));
  const nlohmann::json& verify = group["verify"];
  EXPECT_FALSE(verify.contains("failure")) << verify.dump(2);
  EXPECT_EQ(verify["pixels"], 19200);
  EXPECT_GT(verify["written"].get<int>(), 0);
  EXPECT_GE(verify["nearest_view_depth"].get<double>(), 2.0);
  EXPECT_LE(verify["farthest_view_depth"].get<double>(), far);
  // The frame's depth against the rays of that matrix, through the horse's post-VS positions:
  // consistent, on the pixels the depth buffer shows written.
  const auto reconciled =
      runClipray("reconcile --capture glmark2.rdc --out out --json", folder.path());
  ASSERT_EQ(reconciled.status, 0) << reconciled.err;
  const nlohmann::json run = nlohmann::json::parse(reconciled.out)["runs"][0];
  EXPECT_EQ(run["verdict"], "consistent");
  EXPECT_EQ(run["convention"], "no");
  EXPECT_EQ(run["raster_hits"], verify["written"]);
  EXPECT_EQ(run["coverage_mismatch"]["unexplained"], 0);
  EXPECT_EQ(run["id_mismatch"]["unexplained"], 0);
  EXPECT_EQ(run["depth_beyond_tolerance"], 0);
}

// glmark2-es2's refract scene: the horse drawn into a 640x480 refraction target of its own, then
// into the window with that target projected onto it through a second projection, LightMatrix,
// whose near plane (1.237) reads as a ZO build. gl_Position is computed with
// ModelViewProjectionMatrix: the post-VS positions fit its depth row and not LightMatrix's, so
// LightMatrix is left out with a note instead of a false depth-convention-mismatch error, and the
// frame reconciles consistent, its refraction pass (another depth target) left out of it.
TEST(RealProgramCapture, Glmark2Es2RefractChecksTheCameraNotTheLight) {
  SKIP_WITHOUT("glmark2-es2");
  TempFolder folder;
  const Captured captured =
      captureProgram("refract.rdc", "glmark2-es2 -s 160x120 -b refract:duration=30", folder);
  ASSERT_EQ(captured.status, 0) << captured.output;
  const nlohmann::json report = checkJson("--capture refract.rdc", folder, 0);
  EXPECT_EQ(report["verdict"], "ok");
  const nlohmann::json& findings = report["findings"];
  ASSERT_EQ(codes(findings), std::vector<std::string>{"info:matrix-not-the-camera"});
  EXPECT_EQ(findings[0]["message"].get<std::string>().rfind("uniform LightMatrix (Program ", 0), 0u)
      << findings[0]["message"];
  for (const nlohmann::json& group : report["groups"]) {
    EXPECT_EQ(codes(group["findings"]), std::vector<std::string>{}) << group["source"];
    EXPECT_EQ(group["properties"]["built_for"], "no") << group["source"];
  }
  const auto reconciled =
      runClipray("reconcile --capture refract.rdc --out out --json", folder.path());
  ASSERT_EQ(reconciled.status, 0) << reconciled.err;
  const nlohmann::json run = nlohmann::json::parse(reconciled.out)["runs"][0];
  EXPECT_EQ(run["verdict"], "consistent");
  EXPECT_EQ(run["convention"], "no");
  EXPECT_EQ(run["size"], (nlohmann::json{{"width", 160}, {"height", 120}}));
  EXPECT_GT(run["raster_hits"].get<int>(), 1000);
}

// glxgears draws with legacy GL (glBegin, display lists): RenderDoc registers the context as not
// supported and captures nothing; the capture script says so.
TEST(RealProgramCapture, LegacyGlxgearsIsRefusedByRenderDoc) {
  SKIP_WITHOUT("glxgears");
  TempFolder folder;
  const Captured captured = captureProgram("glxgears.rdc", "glxgears", folder);
  EXPECT_EQ(captured.status, 1);
  EXPECT_NE(captured.output.find("clipray-capture-frame: RenderDoc does not capture glxgears's "
                                 "OpenGL context: Unsupported functions used:  - glBegin"),
            std::string::npos)
      << captured.output;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "glxgears.rdc"));
}

}  // namespace
}  // namespace clipray

// `clipray reconcile --backend egl`: the same report as OSMesa on llvmpipe, and a clear exit 2
// when EGL is missing.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;
const std::string kStandard = "'" + kSource + "/scenes/standard.json'";
// Mesa's surfaceless platform on llvmpipe, the rasterizer OSMesa uses.
const std::string kLlvmpipe = "CLIPRAY_EGL_PLATFORM=surfaceless LIBGL_ALWAYS_SOFTWARE=1";

// EGL is unusable here (no library, no display): the only reason these tests skip.
bool eglUnavailable(const testing::CommandResult& result) {
  return result.status == 2 && (result.err.find("clipray: EGL: cannot load libEGL.so.1") == 0 ||
                                result.err.find("clipray: EGL: no usable display") == 0);
}

TEST(EglCli, ReconcilesWithEgl) {
  TempFolder folder;
  const auto result =
      runClipray("reconcile " + kStandard + " --backend egl --out out --json", folder.path());
  if (eglUnavailable(result)) GTEST_SKIP() << "EGL cannot create a context here: " << result.err;
  ASSERT_EQ(result.status, 0) << result.err;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  EXPECT_EQ(report["gl"]["backend"], "egl");
  EXPECT_NE(report["gl"]["version"].get<std::string>().find("4.5"), std::string::npos);
  ASSERT_EQ(report["runs"].size(), 4u);
  for (const auto& run : report["runs"]) EXPECT_EQ(run["verdict"], "consistent");
  // With --json the summary goes to stderr and stdout holds only the report.
  EXPECT_NE(result.err.find("4 runs: 4 consistent, 0 inconsistent"), std::string::npos)
      << result.err;
}

// Every shipped scene under all three conventions: the reports agree field for field (timings
// aside) and the PNGs byte for byte.
TEST(EglCli, ReportsMatchOsMesaOnLlvmpipe) {
  TempFolder folder;
  std::filesystem::create_directory_symlink(kSource + "/scenes", folder.path() / "scenes");
  const std::string common =
      "reconcile --conventions no,zo,zo-reversed --depth-formats 16,24,32f --size 96x72 "
      "--images all ";
  const auto egl = runClipray(common + "--backend egl --out egl", folder.path(), kLlvmpipe);
  if (eglUnavailable(egl)) GTEST_SKIP() << "EGL cannot create a context here: " << egl.err;
  const auto osMesa = runClipray(common + "--backend osmesa --out osmesa", folder.path());
  // 16-bit depth makes some hard scenes inconsistent (status 1): the same ones on both backends.
  ASSERT_TRUE(osMesa.status == 0 || osMesa.status == 1) << osMesa.err;
  EXPECT_EQ(egl.status, osMesa.status) << egl.err;
  // The text summary, line for line, up to the "report: FOLDER/index.html" line.
  auto summary = [](const std::string& out) { return out.substr(0, out.rfind("report: ")); };
  EXPECT_EQ(summary(egl.out), summary(osMesa.out));
  auto eglReport = nlohmann::json::parse(testing::readText(folder.path() / "egl/report.json"));
  auto osMesaReport =
      nlohmann::json::parse(testing::readText(folder.path() / "osmesa/report.json"));
  ASSERT_NE(eglReport["gl"]["renderer"].get<std::string>().find("llvmpipe"), std::string::npos)
      << eglReport["gl"];
  EXPECT_EQ(eglReport["gl"]["backend"], "egl");
  EXPECT_EQ(osMesaReport["gl"]["backend"], "osmesa");
  EXPECT_EQ(eglReport["gl"]["renderer"], osMesaReport["gl"]["renderer"]);
  ASSERT_EQ(eglReport["runs"].size(), osMesaReport["runs"].size());
  EXPECT_GE(eglReport["runs"].size(), 10u * 3 * 3);
  for (std::size_t k = 0; k < eglReport["runs"].size(); ++k) {
    nlohmann::json& ours = eglReport["runs"][k];
    nlohmann::json& theirs = osMesaReport["runs"][k];
    for (const char* timed : {"timings_ms", "cpu_ms", "analytic_over_raster"}) {
      ours.erase(timed);
      theirs.erase(timed);
    }
    EXPECT_EQ(ours, theirs) << "run " << k;
    for (const auto& [name, path] : ours["images"].items()) {
      const std::string file = path.get<std::string>();
      EXPECT_EQ(testing::readText(folder.path() / "egl" / file),
                testing::readText(folder.path() / "osmesa" / file))
          << file;
    }
  }
}

TEST(EglCli, AMissingLibraryExitsTwoAndWritesNothing) {
  TempFolder folder;
  const auto result = runClipray("reconcile " + kStandard + " --backend egl", folder.path(),
                                 "CLIPRAY_EGL_LIBRARY=/nonexistent/libEGL.so.1");
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err.rfind("clipray: EGL: cannot load /nonexistent/libEGL.so.1 (", 0), 0u)
      << result.err;
  EXPECT_NE(result.err.find("install Debian's libegl1 and libegl-mesa0"), std::string::npos)
      << result.err;
  EXPECT_TRUE(std::filesystem::is_empty(folder.path())) << "outputs were written";
}

TEST(EglCli, NoUsableDisplayExitsTwo) {
  TempFolder folder;
  // glvnd's libEGL with no vendor library: no platform, no device.
  const auto result = runClipray("reconcile " + kStandard + " --backend egl", folder.path(),
                                 "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/vendor.json");
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: EGL: no usable display: libEGL.so.1 offers neither the surfaceless platform "
            "(EGL_MESA_platform_surfaceless) nor a device (EGL_EXT_platform_device); install "
            "Mesa's libegl-mesa0 or a GPU driver's EGL vendor library\n");
  EXPECT_TRUE(std::filesystem::is_empty(folder.path())) << "outputs were written";
}

TEST(EglCli, ALibraryThatIsNotEglExitsTwo) {
  TempFolder folder;
  // A library that is not EGL at all: the backend says what is missing.
  const auto result = runClipray("reconcile " + kStandard + " --backend egl", folder.path(),
                                 "CLIPRAY_EGL_LIBRARY=libOSMesa.so.8");
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err, "clipray: EGL: eglGetProcAddress missing from the loaded library\n");
  EXPECT_TRUE(std::filesystem::is_empty(folder.path())) << "outputs were written";
}

TEST(EglCli, AnUnknownPlatformChoiceExitsTwo) {
  TempFolder folder;
  const auto result = runClipray("reconcile " + kStandard + " --backend egl", folder.path(),
                                 "CLIPRAY_EGL_PLATFORM=x11");
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: EGL: CLIPRAY_EGL_PLATFORM: unknown value \"x11\"; expected one of: auto, "
            "surfaceless, device\n");
}

}  // namespace
}  // namespace clipray

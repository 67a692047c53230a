// clipray-pick: the mouse-picking demo. A click is picked three ways (analytic ray, depth readback,
// id buffer) and the answers are shown side by side. See README.md, "Picking demo".

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <sstream>

#include "PickDemo.hpp"
#include "PickScript.hpp"
#include "cli/ParseErrors.hpp"
#include "clipray/InputError.hpp"
#include "clipray/scene/Scene.hpp"
#include "clipray/util/ExitStatus.hpp"
#include "clipray/util/Version.hpp"

namespace {

using namespace clipray;

glm::ivec2 parseWindowSize(const std::string& text) {
  int width = 0, height = 0;
  char x = 0;
  std::istringstream stream(text);
  if (!(stream >> width >> x >> height) || x != 'x' || !stream.eof() || width <= 0 || height <= 0 ||
      width > 16384 || height > 16384) {
    throw InputError(
        "--size: expected WxH with whole numbers from 1 to 16384 (e.g. 960x640), "
        "got \"" +
        text + "\"");
  }
  return {width, height};
}

std::string defaultScene() {
  const std::string local = "scenes/standard.json";
  if (std::filesystem::is_regular_file(local)) return local;
  return std::string(CLIPRAY_SOURCE_DIR) + "/scenes/standard.json";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "clipray-pick: click on a scene and see the analytic ray, the depth readback and "
      "the id buffer answer side by side"};
  app.set_version_flag("--version", "clipray-pick " + clipray::versionString(),
                       "Print the version (and git commit) and exit");
  std::string scenePath;
  std::string convention = "zo", depthFormat = "24", method = "robust", precision = "float";
  std::string vertexMode = "world";
  std::string size = "960x640", scriptPath, screenshotPath;
  app.add_option("scene", scenePath, "Scene file (default: scenes/standard.json)");
  app.add_option("--convention", convention,
                 "no, zo or zo-reversed, each also with -upper-left (drawn under "
                 "glClipControl(GL_UPPER_LEFT, ...))")
      ->capture_default_str();
  app.add_option("--depth-format", depthFormat, "16, 24 or 32f")->capture_default_str();
  app.add_option("--method", method,
                 "Ray method (clipray's ray library): unproject_glm, two_point, inverse_pv, "
                 "fov_tangent, plane_cross, plane_cross_pre, full or robust; the M key cycles "
                 "through all of them in float, then robust double")
      ->capture_default_str();
  app.add_option("--precision", precision, "Precision of the ray method: float or double")
      ->capture_default_str();
  app.add_option("--vertex-mode", vertexMode, "world, camera-relative or pretransformed")
      ->capture_default_str();
  app.add_option("--size", size, "Window size WxH in screen units")->capture_default_str();
  app.add_option("--script", scriptPath,
                 "Replay clicks, drags, wheel steps, keys and resizes from FILE, print one JSON "
                 "line per pick, then exit");
  app.add_option("--screenshot", screenshotPath,
                 "Save the window's framebuffer as a PNG after the script (or the first frames)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version print what they were asked for; every other parse error is one line
    // and status 2.
    if (error.get_exit_code() == 0) return app.exit(error);
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    std::cerr << "clipray-pick: "
              << clipray::cli::parseErrorText(error, app, arguments, "clipray-pick") << "\n";
    return 2;
  }

  try {
    // Everything the user handed us is checked before any window opens.
    demo::DemoSettings settings;
    // An -upper-left name draws under glClipControl(GL_UPPER_LEFT, ...); the picks take the
    // camera as a lower-left origin numbers the rows read back (lowerLeftCameraInputs).
    const auto mode = DepthMode::parse(convention);
    if (!mode) {
      throw InputError("--convention: unknown value \"" + convention +
                       "\"; expected one of: no, zo, zo-reversed (each also with -upper-left)");
    }
    settings.mode = *mode;
    const auto format = parseDepthFormat(depthFormat);
    if (!format) {
      throw InputError("--depth-format: unknown value \"" + depthFormat +
                       "\"; expected one of: 16, 24, 32f");
    }
    settings.depthFormat = *format;
    const auto rayMethod = parseRayMethod(method);
    if (!rayMethod) {
      std::string names;
      for (const RayMethod known : kRayMethods) {
        names += (names.empty() ? "" : ", ") + rayMethodName(known);
      }
      throw InputError("--method: unknown value \"" + method + "\"; expected one of: " + names);
    }
    settings.ray.method = *rayMethod;
    if (precision != "float" && precision != "double") {
      throw InputError("--precision: unknown value \"" + precision +
                       "\"; expected one of: float, double");
    }
    settings.ray.precision = precision == "float" ? Precision::Float : Precision::Double;
    const auto vertices = parseVertexMode(vertexMode);
    if (!vertices) {
      throw InputError("--vertex-mode: unknown value \"" + vertexMode +
                       "\"; expected one of: world, camera-relative, pretransformed");
    }
    settings.vertexMode = *vertices;
    settings.windowSize = parseWindowSize(size);
    Scene scene = loadScene(scenePath.empty() ? defaultScene() : scenePath);
    if (scene.cameras.empty()) throw InputError(scene.path + ": /cameras: the demo needs a camera");
    std::vector<demo::ScriptCommand> script;
    if (!scriptPath.empty()) script = demo::loadScript(scriptPath);
    if (!screenshotPath.empty()) {
      const std::filesystem::path parent = std::filesystem::path(screenshotPath).parent_path();
      if (!parent.empty() && !std::filesystem::is_directory(parent)) {
        throw InputError("--screenshot: " + screenshotPath + ": folder " + parent.string() +
                         " does not exist");
      }
      if (std::filesystem::path(screenshotPath).extension() != ".png") {
        throw InputError("--screenshot: " + screenshotPath + ": expected a .png file name");
      }
    }

    demo::PickDemo pickDemo(std::move(scene), settings, std::cout);
    if (!scriptPath.empty() || !screenshotPath.empty()) {
      pickDemo.runScript(script);
    } else {
      pickDemo.runInteractive();
    }
    if (!screenshotPath.empty()) pickDemo.saveScreenshot(screenshotPath);
    return 0;
  } catch (const std::exception& error) {
    // Bad input, no display, no GL 4.5: a message and status 2; a broken invariant (a bug):
    // "internal error, please report" and status 3. Never a crash.
    return clipray::reportFailure(error, std::cerr, "clipray-pick");
  }
}

// `clipray check`: a convention checker for GL apps' matrices.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

#include "Commands.hpp"
#include "Parsing.hpp"
#include "clipray/check/ConventionCheck.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/VerifyCheck.hpp"
#include "clipray/scene/InputError.hpp"
#include "clipray/scene/InputFile.hpp"
#include "clipray/scene/SceneJson.hpp"

namespace clipray::cli {

namespace {

struct CheckOptions {
  std::string file;
  std::string clipFromWorld, projection, view;
  std::string layout = "column-major";
  std::string declaredDepth;
  bool reversed = false;
  std::string depthRange;
  std::string origin;
  std::string viewport = "1920x1080";
  std::string depthBits = "24";
  std::string sceneExtent;
  std::string precision;
  std::string nearPlane, farPlane;
  bool json = false;
  bool verify = false;
  std::string backend = "osmesa";
  std::size_t optionsGiven =
      0;  // field options on the command line (not --json/--verify/--backend)
};

std::string requireOneOf(const std::string& value, const std::string& what,
                         const std::vector<std::string>& valid) {
  for (const std::string& v : valid) {
    if (v == value) return value;
  }
  throw InputError(what + ": unknown value \"" + value +
                   "\"; expected one of: " + joinNames(valid));
}

// The same fields from a JSON file (keys in camelCase, matrices as arrays of 16 numbers).
void readCheckFile(CheckOptions& options) {
  // The scene files' reader: line and column for malformed JSON, duplicate keys, NUL bytes and
  // deep nesting refused, a size cap.
  nlohmann::json doc = detail::parseJson(
      readInputFile(options.file, kMaxCheckFileBytes, "check file"), options.file);
  if (!doc.is_object()) throw InputError(options.file, "/", "expected an object");
  auto text = [&](const char* key) -> std::string {
    const auto& value = doc[key];
    if (value.is_string()) return value.get<std::string>();
    if (value.is_array()) {
      std::string joined;
      for (const auto& item : value) {
        if (!item.is_number())
          throw InputError(options.file, std::string("/") + key,
                           "expected numbers, got " + item.dump());
        joined += item.dump() + " ";
      }
      return joined;
    }
    throw InputError(options.file, std::string("/") + key,
                     "expected a string or an array of numbers, got " + value.dump());
  };
  for (const auto& [key, value] : doc.items()) {
    if (key == "clipFromWorld")
      options.clipFromWorld = text("clipFromWorld");
    else if (key == "projection")
      options.projection = text("projection");
    else if (key == "view")
      options.view = text("view");
    else if (key == "sceneExtent")
      options.sceneExtent = text("sceneExtent");
    else if (key == "depthRange")
      options.depthRange = text("depthRange");
    else if (key == "near" && value.is_number())
      options.nearPlane = value.dump();
    else if (key == "far" && value.is_number())
      options.farPlane = value.dump();
    else if (key == "precision" && value.is_string())
      options.precision = value.get<std::string>();
    else if (key == "layout" && value.is_string())
      options.layout = value.get<std::string>();
    else if (key == "declaredDepth" && value.is_string())
      options.declaredDepth = value.get<std::string>();
    else if (key == "origin" && value.is_string())
      options.origin = value.get<std::string>();
    else if (key == "viewport" && value.is_string())
      options.viewport = value.get<std::string>();
    else if (key == "viewport" && value.is_array() && value.size() == 2 &&
             value[0].is_number_integer() &&
             value[1].is_number_integer())  // [W, H], as scene files write it
      options.viewport = value[0].dump() + "x" + value[1].dump();
    else if (key == "depthBits" && value.is_string())
      options.depthBits = value.get<std::string>();
    else if (key == "depthBits" && value.is_number_integer())  // 16 or 24 as a number
      options.depthBits = value.dump();
    else if (key == "reversed" && value.is_boolean())
      options.reversed = value.get<bool>();
    else if (key == "comment")
      continue;
    else {
      throw InputError(
          options.file, "/" + key,
          "unknown key or wrong type (" + value.dump() +
              "); valid keys: clipFromWorld, projection, view, layout, declaredDepth, reversed, "
              "depthRange, origin, viewport, depthBits, sceneExtent, precision, near, far, "
              "comment");
    }
  }
}

int runCheck(CheckOptions options) {
  if (!options.file.empty()) {
    // One source of truth: a file's fields are not silently overridden or mixed with options.
    if (options.optionsGiven > 0) {
      throw InputError(options.file + ": give the fields in the file or as options, not both");
    }
    readCheckFile(options);
  }
  const std::string where = options.file.empty() ? "" : options.file + ": ";
  if (options.clipFromWorld.empty() == options.projection.empty()) {
    throw InputError(
        where +
        (options.clipFromWorld.empty()
             ? "give the matrix: --clip-from-world \"16 numbers\", or --projection (with --view)"
             : "--clip-from-world and --projection are exclusive: give one"));
  }
  if (!options.view.empty() && options.projection.empty()) {
    throw InputError(
        where + "--view needs --projection (for a combined matrix use --clip-from-world alone)");
  }
  // xmmatrix: a DirectXMath matrix in memory is the column-major listing of the GL matrix.
  const bool rowMajor = requireOneOf(options.layout, where + "--layout",
                                     {"column-major", "row-major", "xmmatrix"}) == "row-major";
  CheckInput input;
  if (!options.clipFromWorld.empty()) {
    input.clipFromWorld =
        parseMatrixOption(options.clipFromWorld, rowMajor, where + "--clip-from-world");
  } else {
    input.projection = parseMatrixOption(options.projection, rowMajor, where + "--projection");
    input.view = options.view.empty() ? glm::dmat4(1.0)
                                      : parseMatrixOption(options.view, rowMajor, where + "--view");
    input.clipFromWorld = *input.projection * *input.view;
  }
  if (!options.declaredDepth.empty()) {
    input.declaredDepth =
        requireOneOf(options.declaredDepth, where + "--declared-depth", {"no", "zo"}) == "zo"
            ? DepthConvention::ZeroToOne
            : DepthConvention::NegativeOneToOne;
  }
  input.declaredReversed = options.reversed;
  if (!options.depthRange.empty()) {
    const std::vector<double> range = parseNumberList(options.depthRange, where + "--depth-range");
    // Written so that NaN fails too.
    if (range.size() != 2 || !(range[0] >= 0 && range[0] <= 1 && range[1] >= 0 && range[1] <= 1)) {
      throw InputError(where + "--depth-range: expected NEAR,FAR in [0, 1], got \"" +
                       options.depthRange + "\"");
    }
    input.depthRange = {range[0], range[1]};
  }
  if (!options.origin.empty()) {
    input.origin = requireOneOf(options.origin, where + "--origin", {"lower-left", "upper-left"}) ==
                           "upper-left"
                       ? WindowOrigin::UpperLeft
                       : WindowOrigin::LowerLeft;
  }
  input.viewport = parseViewportOption(options.viewport, where + "--viewport");
  input.depthFormat = *parseDepthFormat(
      requireOneOf(options.depthBits, where + "--depth-bits", {"16", "24", "32f"}));
  if (!options.sceneExtent.empty()) {
    const std::vector<double> e = parseNumberList(options.sceneExtent, where + "--scene-extent");
    const bool finite = std::all_of(e.begin(), e.end(), [](double v) { return std::isfinite(v); });
    if (e.size() != 6 || !finite || e[0] > e[3] || e[1] > e[4] || e[2] > e[5]) {
      throw InputError(
          where +
          "--scene-extent: expected \"minx miny minz maxx maxy maxz\", finite, min <= max, got \"" +
          options.sceneExtent + "\"");
    }
    input.sceneExtent = std::make_pair(glm::dvec3(e[0], e[1], e[2]), glm::dvec3(e[3], e[4], e[5]));
  }
  if (!options.precision.empty()) {
    input.precision =
        requireOneOf(options.precision, where + "--precision", {"float", "double"}) == "float"
            ? EntryPrecision::Arithmetic::Float32
            : EntryPrecision::Arithmetic::Double;
  }
  const auto plane = [&](const std::string& text, const std::string& what) {
    const std::vector<double> value = parseNumberList(text, where + what);
    if (value.size() != 1 || !std::isfinite(value[0])) {
      throw InputError(where + what + ": expected one finite number, got \"" + text + "\"");
    }
    return value[0];
  };
  if (!options.nearPlane.empty()) input.statedNear = plane(options.nearPlane, "--near");
  if (!options.farPlane.empty()) input.statedFar = plane(options.farPlane, "--far");
  if (input.statedNear && input.statedFar && !(*input.statedFar > *input.statedNear)) {
    throw InputError(where + "--far: expected a number greater than --near (" + options.nearPlane +
                     "), got " + options.farPlane);
  }
  if (!input.declaredDepth && input.declaredReversed) {
    // Reversed-Z without a declared depth mode: the GL default, NEGATIVE_ONE_TO_ONE, is what runs.
    input.declaredDepth = DepthConvention::NegativeOneToOne;
  }
  const CheckReport report = checkConventions(input);
  std::optional<gl::VerifyResult> verified;
  std::string verifiedWith;
  if (options.verify) {
    // Backed by pixels: the app's matrix under the app's conventions on a real rasterizer.
    std::unique_ptr<gl::GlContext> context = gl::createContext(options.backend);
    gl::Renderer renderer(*context);
    verified = gl::verifyCheck(input, report, renderer);
    verifiedWith = options.backend + ", " + renderer.info().renderer;
  }
  if (options.json) {
    nlohmann::json json = checkReportJson(report, input);
    if (verified) {
      json["verify"] = gl::verifyResultJson(*verified);
      json["verify"]["backend"] = verifiedWith;
    }
    std::cout << json.dump(2) << "\n";
  } else {
    std::cout << checkReportText(report, input);
    if (verified) {
      std::cout << "verify (" << verifiedWith << "):\n";
      for (const std::string& line : verified->observations) std::cout << "  " << line << "\n";
    }
  }
  return report.hasErrors() ? 1 : 0;
}

CommandRunner addCheckOptions(CLI::App& app) {
  auto options = std::make_shared<CheckOptions>();
  app.add_option("file", options->file,
                 "A JSON file with the same fields (clipFromWorld, declaredDepth, ...)");
  app.add_option("--clip-from-world", options->clipFromWorld,
                 "The world-to-clip matrix: 16 numbers");
  app.add_option("--projection", options->projection, "The projection (clipFromView): 16 numbers");
  app.add_option("--view", options->view, "The view (viewFromWorld): 16 numbers");
  app.add_option("--layout", options->layout,
                 "Order of the 16 numbers. column-major: a GL mat4 in memory (glm::value_ptr, "
                 "glUniformMatrix4fv with transpose GL_FALSE); a DirectXMath XMMATRIX in memory is "
                 "this order too (alias xmmatrix: row vectors store the transpose). row-major: the "
                 "matrix written row by row, as in a maths text or a C array m[row][col]")
      ->capture_default_str();
  app.add_option("--declared-depth", options->declaredDepth,
                 "What the app draws under: no or zo (glClipControl)");
  app.add_flag("--reversed", options->reversed, "The app draws reversed-Z (GL_GREATER, clear 0)");
  app.add_option("--depth-range", options->depthRange, "glDepthRange NEAR,FAR (default 0,1)");
  app.add_option("--origin", options->origin,
                 "Window y origin of the app's picking: lower-left or upper-left");
  app.add_option("--viewport", options->viewport, "Framebuffer size WxH")->capture_default_str();
  app.add_option("--depth-bits", options->depthBits, "Depth buffer: 16, 24 or 32f")
      ->capture_default_str();
  app.add_option("--scene-extent", options->sceneExtent,
                 "World box of the geometry: minx miny minz maxx maxy maxz");
  app.add_option("--precision", options->precision,
                 "Arithmetic the app built the matrix in: float or double (default: detected from "
                 "the values; short decimals count as float)");
  app.add_option("--near", options->nearPlane,
                 "The near plane the app meant: settles a matrix that reads as NO or ZO");
  app.add_option("--far", options->farPlane, "The far plane the app meant (checked)");
  app.add_flag("--json", options->json, "Print the report as JSON");
  app.add_flag(
      "--verify", options->verify,
      "Render a probe scene with the matrix under the declared conventions and reconcile it");
  app.add_option("--backend", options->backend, "GL backend for --verify: osmesa, egl")
      ->capture_default_str();
  return [options, &app] {
    for (const char* name :
         {"--clip-from-world", "--projection", "--view", "--layout", "--declared-depth",
          "--reversed", "--depth-range", "--origin", "--viewport", "--depth-bits", "--scene-extent",
          "--precision", "--near", "--far"}) {
      options->optionsGiven += app.count(name);
    }
    return runCheck(*options);
  };
}

const bool registered = registerCommand(
    {"check",
     "Diagnose a GL app's matrix and declared conventions (NO/ZO, reversed-Z, transposed, ...)", 10,
     addCheckOptions});

}  // namespace
}  // namespace clipray::cli

// `clipray check`: a convention checker for GL apps' matrices.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "Commands.hpp"
#include "clipray/InputError.hpp"
#include "clipray/check/CheckFields.hpp"
#include "clipray/check/ConventionCheck.hpp"
#include "clipray/engine/VerifyCheck.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/io/InputFile.hpp"
#include "clipray/page/PageCheck.hpp"
#include "clipray/trace/CaptureFileCheck.hpp"
#include "clipray/trace/TraceFileCheck.hpp"
#include "clipray/util/OptionValues.hpp"

namespace clipray::cli {

namespace {

struct CheckOptions {
  std::string file;
  CheckFields fields;
  bool json = false;
  bool verify = false;
  std::string backend = "osmesa";
  std::string trace;              // --trace: an apitrace trace of the app instead of typed numbers
  std::string frames;             // --frames A-B with --trace, N with --page
  std::string page;               // --page: a WebGL page in headless chromium
  std::optional<double> timeout;  // --timeout S with --page
  std::string capture;            // --capture: a RenderDoc capture of the app's frame
  std::string draws;              // --draws A-B with --capture (event IDs)
  std::size_t optionsGiven =
      0;  // field options on the command line (not --json/--verify/--backend)
};

// --frames N with --page: a whole number of animation frames.
std::uint64_t parseFrameCount(const std::string& text) {
  std::uint64_t count = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), count);
  if (error != std::errc() || end != text.data() + text.size() || count == 0 || count > 100000) {
    throw InputError("--frames: expected a number of frames from 1 to 100000 with --page, got '" +
                     text + "'");
  }
  return count;
}

int runTraceCheck(const CheckOptions& options) {
  // The trace is the app's own state: typed fields would contradict it.
  if (!options.file.empty() || options.optionsGiven > 0) {
    throw InputError(
        "--trace: the depth state and matrices come from the trace; give no check "
        "file or field options with it");
  }
  trace::TraceCheckResult result = trace::checkTrace(options.trace, options.frames);
  if (options.verify) trace::verifyTrace(options.trace, result);
  if (options.json) {
    // The trace's path is the user's bytes: not necessarily UTF-8.
    std::cout << trace::traceCheckJson(result).dump(2, ' ', false,
                                                    nlohmann::json::error_handler_t::replace)
              << "\n";
  } else {
    std::cout << trace::traceCheckText(result);
  }
  return result.hasErrors() ? 1 : 0;
}

int runPageCheck(const CheckOptions& options) {
  // The page is the app: typed fields would contradict what it does.
  if (!options.file.empty() || options.optionsGiven > 0 || !options.trace.empty() ||
      !options.capture.empty()) {
    throw InputError(
        "--page: the depth state and matrices come from the page; give no check file, field "
        "options, --trace or --capture with it");
  }
  page::PageOptions pageOptions;
  pageOptions.target = options.page;
  if (!options.frames.empty()) {
    pageOptions.frames = parseFrameCount(options.frames);
  }
  if (options.timeout) pageOptions.timeoutSeconds = *options.timeout;
  pageOptions.verify = options.verify;
  const page::PageCheckResult result = page::checkPage(pageOptions);
  if (options.json) {
    // The page's address and names are the page's bytes: not necessarily UTF-8.
    std::cout << page::pageCheckJson(result).dump(2, ' ', false,
                                                  nlohmann::json::error_handler_t::replace)
              << "\n";
  } else {
    std::cout << page::pageCheckText(result);
  }
  return result.hasErrors() ? 1 : 0;
}

// The capture's draws through the trace checker's model (trace/CaptureFileCheck.hpp).
int runCaptureCheck(const CheckOptions& options) {
  if (!options.file.empty() || options.optionsGiven > 0 || !options.trace.empty()) {
    throw InputError(
        "--capture: the depth state and matrices come from the capture; give no check file, "
        "--trace or field options with it");
  }
  if (!options.frames.empty()) throw InputError("--frames needs --trace (--capture takes --draws)");
  trace::CaptureCheckResult result = trace::checkCapture(options.capture, options.draws);
  if (options.verify) trace::verifyCapture(options.capture, result);
  if (options.json) {
    std::cout << trace::captureCheckJson(result).dump(2, ' ', false,
                                                      nlohmann::json::error_handler_t::replace)
              << "\n";
  } else {
    std::cout << trace::captureCheckText(result);
  }
  return result.check.hasErrors() ? 1 : 0;
}

int runCheck(CheckOptions options) {
  if (!options.page.empty()) return runPageCheck(options);
  if (options.timeout) throw InputError("--timeout needs --page");
  if (!options.capture.empty()) return runCaptureCheck(options);
  if (!options.draws.empty()) throw InputError("--draws needs --capture");
  if (!options.trace.empty()) return runTraceCheck(options);
  if (!options.frames.empty()) throw InputError("--frames needs --trace or --page");
  if (!options.file.empty()) {
    // One source of truth: a file's fields are not silently overridden or mixed with options.
    if (options.optionsGiven > 0) {
      throw InputError(options.file + ": give the fields in the file or as options, not both");
    }
    // The same reader as every file a user names: regular files only, a size cap.
    options.fields =
        parseCheckFile(readInputFile(options.file, kMaxCheckFileBytes, "check file"), options.file);
  }
  const CheckInput input =
      checkInputFrom(options.fields, options.file.empty() ? "" : options.file + ": ");
  const CheckReport report = checkConventions(input);
  std::optional<engine::VerifyResult> verified;
  std::string verifiedWith;
  if (options.verify) {
    // Backed by pixels: the app's matrix under the app's conventions on a real rasterizer.
    std::unique_ptr<gl::GlContext> context = gl::createContext(options.backend);
    gl::Renderer renderer(*context);
    verified = engine::verifyCheck(input, report, renderer);
    verifiedWith = options.backend + ", " + renderer.info().renderer;
  }
  if (options.json) {
    nlohmann::json json = checkReportJson(report, input);
    if (verified) {
      json["verify"] = engine::verifyResultJson(*verified);
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
  app.add_option("--clip-from-world", options->fields.clipFromWorld,
                 "The world-to-clip matrix: 16 numbers");
  app.add_option("--projection", options->fields.projection,
                 "The projection (clipFromView): 16 numbers");
  app.add_option("--view", options->fields.view, "The view (viewFromWorld): 16 numbers");
  app.add_option("--layout", options->fields.layout,
                 "Order of the 16 numbers. column-major: a GL mat4 in memory (glm::value_ptr, "
                 "glUniformMatrix4fv with transpose GL_FALSE); a DirectXMath XMMATRIX in memory is "
                 "this order too (alias xmmatrix: row vectors store the transpose). row-major: the "
                 "matrix written row by row, as in a maths text or a C array m[row][col]")
      ->capture_default_str();
  app.add_option(
      "--declared-depth", options->fields.declaredDepth,
      "What the app draws under: no, zo or zo-reversed (glClipControl; zo-reversed: ZO with "
      "GL_GREATER, as --reversed)");
  app.add_flag("--reversed", options->fields.reversed,
               "The app draws reversed-Z (GL_GREATER, clear 0)");
  app.add_option("--depth-range", options->fields.depthRange,
                 "glDepthRange NEAR,FAR (default 0,1)");
  app.add_option("--origin", options->fields.origin,
                 "Window y origin of the app's picking: lower-left or upper-left");
  app.add_option("--viewport", options->fields.viewport, "Framebuffer size WxH")
      ->capture_default_str();
  app.add_option("--depth-bits", options->fields.depthBits, "Depth buffer: 16, 24 or 32f")
      ->capture_default_str();
  app.add_option("--scene-extent", options->fields.sceneExtent,
                 "World box of the geometry: minx miny minz maxx maxy maxz");
  app.add_option("--precision", options->fields.precision,
                 "Arithmetic the app built the matrix in: float or double (default: detected from "
                 "the values; short decimals count as float)");
  app.add_option("--near", options->fields.nearPlane,
                 "The near plane the app meant: settles a matrix that reads as NO or ZO");
  app.add_option("--far", options->fields.farPlane, "The far plane the app meant (checked)");
  app.add_option("--cull", options->fields.cull,
                 "Face culling the app draws with: none, back or front (glCullFace with "
                 "GL_CULL_FACE enabled): checked against the winding the matrix puts on screen");
  app.add_option("--front-face", options->fields.frontFace,
                 "With --cull: the app's glFrontFace, ccw (default) or cw");
  app.add_flag("--depth-clamp", options->fields.depthClamp,
               "The app draws with GL_DEPTH_CLAMP enabled (nothing clipped at near and far): "
               "noted with what it does to picking rays");
  app.add_option("--trace", options->trace,
                 "An apitrace trace of the app (apitrace trace --api egl|glx APP): check every "
                 "projection it draws with under the depth state traced at each draw");
  app.add_option("--page", options->page,
                 "A WebGL page (http(s) or file URL, or an HTML file): load it in headless "
                 "chromium, record its WebGL calls and check them as --trace does");
  app.add_option("--frames", options->frames,
                 "With --trace: frames A-B (from 0) or A only; with --page: record N animation "
                 "frames (default 3)");
  app.add_option("--timeout", options->timeout,
                 "With --page: seconds to wait for the page's frames (default 30)");
  app.add_option("--capture", options->capture,
                 "A RenderDoc capture (.rdc) of an OpenGL core-profile app: check every "
                 "projection its draws use under each draw's replayed state");
  app.add_option("--draws", options->draws,
                 "With --capture: draws with RenderDoc event IDs A-B, or A only");
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
          "--precision", "--near", "--far", "--cull", "--front-face", "--depth-clamp"}) {
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

#pragma once
// `clipray check --trace --verify`: the depth buffer as the app's own calls leave it, replayed
// headlessly by apitrace (`eglretrace -D CALL`, WAFFLE_PLATFORM=surfaceless_egl), read from the
// state JSON it writes, and set against the convention: which window depths the draws used, which
// view depths they are under the traced convention, and where a pick that reads the depth back
// with the convention the matrix was built for would put them.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/trace/TraceCheck.hpp"

namespace clipray::trace {

struct DepthImage {
  int width = 0;
  int height = 0;
  std::string format;  // "GL_DEPTH_COMPONENT32F", "GL_DEPTH_COMPONENT", ...
  std::vector<float> depth;
};

// The depth image of the draw framebuffer in apitrace's state dump (framebuffer.<name> with a
// GL_DEPTH* __format__; __data__ is base64 of a PFM: "Pf\nW H\nscale\n" then W*H floats, which
// apitrace 11.1 writes in the host's (little-endian) order whatever the scale's sign). nullopt
// when the state holds no depth image. Throws std::invalid_argument for malformed JSON or data.
std::optional<DepthImage> depthImageFromState(const std::string& stateJson);

struct DepthUse {
  std::uint64_t call = 0;
  std::uint64_t frame = 0;
  std::uint64_t pixels = 0;
  std::uint64_t written = 0;  // pixels whose depth differs from the cleared value
  double minDepth = 0.0, maxDepth = 0.0;
  std::optional<double> nearestViewDepth, farthestViewDepth;  // under the traced convention
  // Read back with the built-for convention instead (where the two differ): the view depths a
  // pick would compute, and its worst relative error.
  std::optional<double> pickedNearest, pickedFarthest, pickWorstRelativeError;
  std::vector<std::string> observations;
};

// Base64 (RFC 4648, padding optional) to bytes; std::invalid_argument for other characters.
std::string decodeBase64(const std::string& text);

// What the depth image says about the group's matrix under its traced depth state.
DepthUse analyseDepthUse(const DepthImage& image, const TracePairGroup& group);

nlohmann::json depthUseJson(const DepthUse& use);

}  // namespace clipray::trace

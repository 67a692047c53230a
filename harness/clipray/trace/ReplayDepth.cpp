#include "clipray/trace/ReplayDepth.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "clipray/check/CheckText.hpp"

namespace clipray::trace {

std::string decodeBase64(const std::string& text) {
  static const std::string alphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  bytes.reserve(text.size() / 4 * 3);
  unsigned value = 0;
  int bits = 0;
  for (const char c : text) {
    if (c == '=' || c == '\n' || c == '\r' || c == ' ') continue;
    const std::size_t digit = alphabet.find(c);
    if (digit == std::string::npos) throw std::invalid_argument("depth image: not base64");
    value = (value << 6) | static_cast<unsigned>(digit);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes.push_back(static_cast<char>((value >> bits) & 0xFFu));
    }
  }
  return bytes;
}

namespace {

std::string number(double value) {
  return detail::checkNumber(value);
}

// The view depth s along the view direction from the eye at which the matrix gives z_ndc:
// z_ndc (Mw.(eye, 1) + s Mw.(dir, 0)) = Mz.(eye, 1) + s Mz.(dir, 0).
std::optional<double> viewDepthAt(const glm::dmat4& m, const glm::dvec3& eye,
                                  const glm::dvec3& direction, double zNdc) {
  const glm::dvec4 rowZ(m[0][2], m[1][2], m[2][2], m[3][2]);
  const glm::dvec4 rowW(m[0][3], m[1][3], m[2][3], m[3][3]);
  const glm::dvec4 e(eye, 1.0), d(direction, 0.0);
  const double denominator = zNdc * glm::dot(rowW, d) - glm::dot(rowZ, d);
  if (denominator == 0.0) return std::nullopt;
  const double s = (glm::dot(rowZ, e) - zNdc * glm::dot(rowW, e)) / denominator;
  if (!std::isfinite(s)) return std::nullopt;
  return s;
}

// z_ndc from window depth d under glDepthRange(n, f) and the convention.
double ndcOf(double windowDepth, glm::dvec2 range, bool zeroToOne) {
  const double unit = (windowDepth - range.x) / (range.y - range.x);
  return zeroToOne ? unit : 2.0 * unit - 1.0;
}

}  // namespace

std::optional<DepthImage> depthImageFromState(const std::string& stateJson) {
  // apitrace writes shader sources with raw control characters inside JSON strings: blank them.
  std::string text = stateJson;
  for (char& c : text) {
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  nlohmann::json state;
  try {
    state = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw std::invalid_argument(std::string("state dump: ") + error.what());
  }
  if (!state.is_object() || !state.contains("framebuffer") || !state["framebuffer"].is_object()) {
    return std::nullopt;
  }
  for (const auto& [name, image] : state["framebuffer"].items()) {
    if (!image.is_object() || !image.contains("__format__") || !image["__format__"].is_string()) {
      continue;
    }
    const std::string format = image["__format__"];
    if (!format.starts_with("GL_DEPTH")) continue;
    DepthImage result;
    result.format = format;
    const std::string bytes = decodeBase64(image.value("__data__", std::string()));
    std::istringstream header(bytes);
    std::string magic;
    double scale = 0.0;
    header >> magic >> result.width >> result.height >> scale;
    if (magic != "Pf" || result.width <= 0 || result.height <= 0 || !header) {
      throw std::invalid_argument("depth image " + name + ": not a one-channel PFM");
    }
    const std::size_t offset = static_cast<std::size_t>(header.tellg()) + 1;  // one whitespace
    const std::size_t count =
        static_cast<std::size_t>(result.width) * static_cast<std::size_t>(result.height);
    if (bytes.size() < offset + 4 * count) {
      throw std::invalid_argument("depth image " + name + ": " + std::to_string(bytes.size()) +
                                  " bytes, short of " + std::to_string(offset + 4 * count));
    }
    result.depth.resize(count);
    std::memcpy(result.depth.data(), bytes.data() + offset, 4 * count);
    return result;
  }
  return std::nullopt;
}

DepthUse analyseDepthUse(const DepthImage& image, const TracePairGroup& group) {
  DepthUse use;
  use.call = group.first.completedAtCall;
  use.frame = group.first.frame;
  use.pixels = image.depth.size();
  const TraceDepthState& state = group.depth;
  const double cleared = state.clearedDepth.value_or(1.0);
  use.minDepth = HUGE_VAL;
  use.maxDepth = -HUGE_VAL;
  for (const float value : image.depth) {
    // A float depth buffer holds the cleared value exactly; a UNORM one reads back within one
    // 16-bit step of it.
    if (std::abs(static_cast<double>(value) - cleared) <= 0x1p-16) continue;
    ++use.written;
    use.minDepth = std::min(use.minDepth, static_cast<double>(value));
    use.maxDepth = std::max(use.maxDepth, static_cast<double>(value));
  }
  std::ostringstream head;
  head << "depth buffer after call " << use.call << " (frame " << use.frame << "): " << image.width
       << "x" << image.height << " " << image.format << ", " << use.written << " of " << use.pixels
       << " pixels differ from the cleared depth " << number(cleared);
  use.observations.push_back(head.str());
  if (use.written == 0) {
    use.minDepth = use.maxDepth = cleared;
    if (!state.depthWrite) {
      // glDepthMask(GL_FALSE): the draw may pass the test and still write nothing.
      use.observations.push_back("depth writes were off (glDepthMask(GL_FALSE) at call " +
                                 std::to_string(state.depthMaskCall) +
                                 "): this call wrote no depth");
    } else {
      use.observations.push_back(
          state.depthTest ? "no fragment passed the depth test (or none was drawn) by this call"
                          : "nothing was drawn into the depth buffer by this call");
    }
    return use;
  }
  use.observations.push_back("window depth used: " + number(use.minDepth) + " to " +
                             number(use.maxDepth));
  const MatrixProperties& p = group.report.properties;
  if (!group.unusable.empty() || !p.perspective || !p.eye) return use;
  const auto viewDepths = [&](bool zeroToOne) -> std::optional<std::pair<double, double>> {
    const auto a = viewDepthAt(group.matrix, *p.eye, p.viewDirection,
                               ndcOf(use.minDepth, state.depthRange, zeroToOne));
    const auto b = viewDepthAt(group.matrix, *p.eye, p.viewDirection,
                               ndcOf(use.maxDepth, state.depthRange, zeroToOne));
    if (!a || !b) return std::nullopt;
    return std::make_pair(std::min(*a, *b), std::max(*a, *b));
  };
  const auto traced = viewDepths(state.clipZeroToOne);
  if (!traced) return use;
  use.nearestViewDepth = traced->first;
  use.farthestViewDepth = traced->second;
  use.observations.push_back(
      "view depth of those pixels under the traced " +
      std::string(state.clipZeroToOne ? "ZERO_TO_ONE" : "NEGATIVE_ONE_TO_ONE") + ": " +
      number(traced->first) + " to " + number(traced->second));
  const bool builtZeroToOne = p.builtFor == "zo" || p.builtFor == "zo-reversed";
  if (p.builtFor == "ambiguous" || builtZeroToOne == state.clipZeroToOne) return use;
  const auto picked = viewDepths(builtZeroToOne);
  if (!picked) return use;
  use.pickedNearest = picked->first;
  use.pickedFarthest = picked->second;
  use.pickWorstRelativeError = std::max(std::abs(picked->first - traced->first) / traced->first,
                                        std::abs(picked->second - traced->second) / traced->second);
  use.observations.push_back("read back with the convention the matrix was built for (" +
                             p.builtFor +
                             "), as a pick that unprojects the depth does, they land at " +
                             number(picked->first) + " to " + number(picked->second) + ": up to " +
                             number(100.0 * *use.pickWorstRelativeError) + "% off");
  return use;
}

nlohmann::json depthUseJson(const DepthUse& use) {
  const auto optional = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  return {{"call", use.call},
          {"frame", use.frame},
          {"pixels", use.pixels},
          {"written", use.written},
          {"min_depth", use.minDepth},
          {"max_depth", use.maxDepth},
          {"nearest_view_depth", optional(use.nearestViewDepth)},
          {"farthest_view_depth", optional(use.farthestViewDepth)},
          {"picked_nearest", optional(use.pickedNearest)},
          {"picked_farthest", optional(use.pickedFarthest)},
          {"pick_worst_relative_error", optional(use.pickWorstRelativeError)},
          {"observations", use.observations}};
}

}  // namespace clipray::trace

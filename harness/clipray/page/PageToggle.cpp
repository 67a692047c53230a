// The toggled run's rule and its check (PageToggle.hpp).

#include "clipray/page/PageToggle.hpp"

namespace clipray::page {

std::string toggleRefusal(const nlohmann::json& facts, bool reversed) {
  if (!facts.is_object() || !facts.value("setReversed", false)) {
    return "the page's three.js has no reversed depth buffer (WebGLRenderer's depth state has no "
           "setReversed; three.js r169 added it)";
  }
  if (!reversed && !facts.value("clipControl", false)) {
    return "the page's WebGL context has no EXT_clip_control (three.js ignores "
           "reversedDepthBuffer without it)";
  }
  if (facts.value("logarithmicDepthBuffer", false)) {
    return "the page uses a logarithmic depth buffer (three.js turns it off under a reversed depth "
           "buffer: the toggled page would not be one three.js makes)";
  }
  return "";
}

std::string toggleFailure(const nlohmann::json& facts, bool reversed, bool want) {
  const nlohmann::json toggled =
      facts.is_object() ? facts.value("toggled", nlohmann::json::array()) : nlohmann::json();
  if (!toggled.is_array() || toggled.empty()) {
    return "no renderer was toggled (none announced itself to __THREE_DEVTOOLS__)";
  }
  for (const nlohmann::json& entry : toggled) {
    if (entry.is_object() && entry.contains("failure")) {
      return "the renderer could not be toggled (" + entry.value("failure", "") + ")";
    }
  }
  if (reversed != want) {
    return std::string("the page's renderer drew with reversedDepthBuffer ") +
           (reversed ? "on" : "off") + " after the toggle (the page sets it itself)";
  }
  return "";
}

}  // namespace clipray::page

// `clipray check --page --verify` (PageVerify.hpp): the depth images the recorder read back, set
// against the groups by the trace's own analysis (ReplayDepth.hpp).

#include "clipray/page/PageVerify.hpp"

#include <algorithm>
#include <cstring>

#include "clipray/trace/ReplayDepth.hpp"

namespace clipray::page {

void addDepthImages(PageCheckResult& result, const nlohmann::json& images) {
  for (std::size_t k = 0; k < result.canvases.size(); ++k) {
    CanvasCheck& canvas = result.canvases[k];
    if (!canvas.result) continue;
    const nlohmann::json image =
        images.is_array() && k < images.size() ? images[k] : nlohmann::json();
    std::string failure = image.is_object() ? image.value("failure", "") : "no depth image";
    trace::DepthImage depth;
    if (failure.empty()) {
      depth.width = image.value("width", 0);
      depth.height = image.value("height", 0);
      depth.format = image.value("format", "");
      const auto bytes = base64Decoded(image.value("depth", ""));
      const auto pixels = static_cast<std::size_t>(std::max(depth.width, 0)) *
                          static_cast<std::size_t>(std::max(depth.height, 0));
      if (!bytes || pixels == 0 || bytes->size() != pixels * sizeof(float)) {
        failure = "the depth image read back is not width x height floats";
      } else {
        depth.depth.resize(pixels);
        std::memcpy(depth.depth.data(), bytes->data(), bytes->size());
      }
    }
    for (trace::TracePairGroup& group : canvas.result->groups) {
      if (!failure.empty()) {
        group.verifyObservations = {"not verified: " + failure};
        group.verify = {{"failure", failure}};
        continue;
      }
      // The image is the last frame's: the group's last draw is the call it follows.
      trace::TracePairGroup atLast = group;
      atLast.first = group.last;
      const trace::DepthUse use = trace::analyseDepthUse(depth, atLast);
      group.verifyObservations = use.observations;
      group.verify = trace::depthUseJson(use);
    }
  }
}

}  // namespace clipray::page

#pragma once
// `clipray check --page --verify`: each canvas's depth buffer as the last recorded frame left it
// (PageRecorder's readDepth: one entry per canvas, {width, height, format, depth: base64 of
// float32s} or {failure}), set against each of the canvas's groups as `--trace --verify` sets a
// replayed one (ReplayDepth.hpp). A canvas whose depth could not be read has each group say so
// ("not verified: ..."), never an error.

#include <nlohmann/json.hpp>

#include "clipray/page/PageCalls.hpp"

namespace clipray::page {

void addDepthImages(PageCheckResult& result, const nlohmann::json& images);

}  // namespace clipray::page

#include "clipray/engine/AppFrameCaptures.hpp"

#include <system_error>

namespace clipray::engine {

AppFrameCaptures::AppFrameCaptures(const std::string& folder) : folder_(folder), capture_(folder) {}

void AppFrameCaptures::start() {
  written_.clear();
  failure_.clear();
  capture_.start();
}

void AppFrameCaptures::end() {
  written_ = capture_.end();
  failure_ = written_.empty() ? capture_.lastFailure() : "";
}

void AppFrameCaptures::settle(std::span<RunRecord* const> runs) {
  bool failing = false;
  for (const RunRecord* run : runs) failing = failing || runVerdict(*run) != RunVerdict::Consistent;
  if (!failing) {
    std::error_code ignored;
    if (!written_.empty()) std::filesystem::remove(written_, ignored);
    written_.clear();
    return;
  }
  if (written_.empty()) {
    for (RunRecord* run : runs) {
      run->notes.push_back("ReconcileOptions::renderDocCaptures: no capture of this frame: " +
                           failure_);
    }
    return;
  }
  const RunRecord& first = *runs.front();
  const std::filesystem::path kept =
      folder_ / (pathComponent(first.scene) + "-" + pathComponent(first.camera) + "-" +
                 first.convention.name() + "-" + depthFormatName(first.depthFormat) + ".rdc");
  gl::RenderDocFrameCapture::keep(written_, kept);
  written_.clear();
  for (RunRecord* run : runs) run->capture = kept.string();
}

}  // namespace clipray::engine

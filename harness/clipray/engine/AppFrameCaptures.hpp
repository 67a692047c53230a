#pragma once
// RenderDoc captures of the frames an app's render function draws (ReconcileOptions::
// renderDocCaptures, gl/RenderDocCapture.hpp): every app frame is captured while RenderDoc is
// loaded into the process; the frame of a failing run is kept in the folder as
// <scene>-<camera>-<convention>-<depth format>.rdc and named in the run (RunRecord::capture), a
// passing run's is removed. Without RenderDoc (or on a context it does not hook) a failing run
// gets a note saying why it has no capture.

#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "clipray/gl/RenderDocCapture.hpp"
#include "clipray/report/Report.hpp"

namespace clipray::engine {

class AppFrameCaptures {
 public:
  explicit AppFrameCaptures(const std::string& folder);

  // Around the app's frame.
  void start();
  void end();
  // After the frame's runs are compared (every sample's run of a multisampled frame): keeps the
  // frame when any of them fails, under the first run's name, and names it in each; else removes
  // it. Throws std::runtime_error where the file cannot be moved.
  void settle(std::span<RunRecord* const> runs);

 private:
  std::filesystem::path folder_;
  gl::RenderDocFrameCapture capture_;
  std::filesystem::path written_;  // the last frame's file; empty: none
  std::string failure_;            // why there is none
};

}  // namespace clipray::engine

#pragma once
// RenderDoc's in-app API (renderdoc_app.h, Debian's librenderdoc-dev) when librenderdoc.so is
// loaded into the process (LD_PRELOAD=librenderdoc.so, or RenderDoc's UI launching the test):
// each frame the app's render function draws is captured, so that a failing run hands the
// developer the frame as a .rdc to open in RenderDoc or give to `clipray reconcile --capture`
// (ReconcileOptions::renderDocCaptures). RenderDoc captures the EGL and GLX contexts it hooks:
// the "egl" backend's, not OSMesa's.

#include <filesystem>
#include <string>

namespace clipray::gl {

class RenderDocFrameCapture {
 public:
  // Finds the API in the process (nothing is loaded: RTLD_NOLOAD). Captures are written into
  // folder (created if missing) under temporary names until kept.
  explicit RenderDocFrameCapture(std::filesystem::path folder);

  // Whether RenderDoc is loaded and its API answered; unavailable() says why not.
  bool available() const { return api_ != nullptr; }
  const std::string& unavailable() const { return unavailable_; }

  // Around one frame, on the context current: StartFrameCapture(NULL, NULL) and EndFrameCapture.
  // end() returns the file RenderDoc wrote, or an empty path where it captured nothing (a context
  // it does not hook), with why in lastFailure().
  void start();
  std::filesystem::path end();
  const std::string& lastFailure() const { return lastFailure_; }

  // Moves a written capture to `path` (replacing a file there); throws std::runtime_error.
  static void keep(const std::filesystem::path& written, const std::filesystem::path& path);

 private:
  void* api_ = nullptr;  // RENDERDOC_API_1_4_2*
  std::filesystem::path folder_;
  std::string unavailable_;
  std::string lastFailure_;
};

}  // namespace clipray::gl

#include "clipray/gl/RenderDocCapture.hpp"

#include <dlfcn.h>

#include <cstdint>
#include <stdexcept>
#include <system_error>
#include <vector>

#ifdef CLIPRAY_HAVE_RENDERDOC_APP
#include <renderdoc_app.h>
#endif

namespace clipray::gl {

#ifdef CLIPRAY_HAVE_RENDERDOC_APP

namespace {

RENDERDOC_API_1_4_2* apiOf(void* api) {
  return static_cast<RENDERDOC_API_1_4_2*>(api);
}

}  // namespace

RenderDocFrameCapture::RenderDocFrameCapture(std::filesystem::path folder)
    : folder_(std::move(folder)) {
  // RTLD_NOLOAD: only a RenderDoc already in the process (renderdoc_app.h, "RENDERDOC_GetAPI").
  void* library = dlopen("librenderdoc.so", RTLD_NOW | RTLD_NOLOAD);
  if (!library) {
    unavailable_ =
        "RenderDoc is not loaded into the process (run the test with "
        "LD_PRELOAD=librenderdoc.so, Debian's librenderdoc)";
    return;
  }
  const auto getApi = reinterpret_cast<pRENDERDOC_GetAPI>(dlsym(library, "RENDERDOC_GetAPI"));
  void* api = nullptr;
  if (!getApi || getApi(eRENDERDOC_API_Version_1_4_2, &api) != 1 || !api) {
    unavailable_ = "the loaded librenderdoc.so offers no in-app API 1.4.2";
    return;
  }
  std::error_code error;
  std::filesystem::create_directories(folder_, error);
  if (error) {
    unavailable_ = "cannot create " + folder_.string() + ": " + error.message();
    return;
  }
  api_ = api;
  // RenderDoc appends _frameN.rdc (or _capture.rdc) to the template.
  apiOf(api_)->SetCaptureFilePathTemplate((folder_ / "clipray-frame").c_str());
}

void RenderDocFrameCapture::start() {
  if (!api_) return;
  // Device and window NULL: the context current on this thread (renderdoc_app.h).
  apiOf(api_)->StartFrameCapture(nullptr, nullptr);
}

std::filesystem::path RenderDocFrameCapture::end() {
  lastFailure_.clear();
  if (!api_) {
    lastFailure_ = unavailable_;
    return {};
  }
  RENDERDOC_API_1_4_2* api = apiOf(api_);
  if (api->EndFrameCapture(nullptr, nullptr) != 1) {
    lastFailure_ =
        "RenderDoc captured nothing: it captures the EGL and GLX contexts it hooks, not "
        "OSMesa's (ReconcileOptions::backend \"egl\")";
    return {};
  }
  std::uint32_t length = 0;
  const std::uint32_t index = api->GetNumCaptures() - 1;
  if (api->GetCapture(index, nullptr, &length, nullptr) != 1 || length == 0) {
    lastFailure_ = "RenderDoc lists no capture after the frame";
    return {};
  }
  std::vector<char> name(length + 1, '\0');
  api->GetCapture(index, name.data(), &length, nullptr);
  return std::filesystem::path(name.data());
}

#else

RenderDocFrameCapture::RenderDocFrameCapture(std::filesystem::path folder)
    : folder_(std::move(folder)),
      unavailable_(
          "clipray was built without RenderDoc's renderdoc_app.h (Debian's librenderdoc-dev)") {}

void RenderDocFrameCapture::start() {}

std::filesystem::path RenderDocFrameCapture::end() {
  lastFailure_ = unavailable_;
  return {};
}

#endif

void RenderDocFrameCapture::keep(const std::filesystem::path& written,
                                 const std::filesystem::path& path) {
  std::error_code error;
  std::filesystem::rename(written, path, error);
  if (error) {
    throw std::runtime_error("cannot move the RenderDoc capture " + written.string() + " to " +
                             path.string() + ": " + error.message());
  }
}

}  // namespace clipray::gl

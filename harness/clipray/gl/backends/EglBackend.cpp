// EGL backend: a headless GL 4.5 core context without any surface (EGL_KHR_surfaceless_context),
// on the EGL device platform when a GPU driver offers a device, else on Mesa's surfaceless
// platform (llvmpipe when no render node is usable). libEGL is opened with dlopen, like OSMesa, so
// that its absence is a clear "EGL: ..." error (exit 2) and clipray has no link-time dependency on
// it. The EGL headers are used for types and constants only.
//
// CLIPRAY_EGL_LIBRARY overrides the library path; CLIPRAY_EGL_PLATFORM = surfaceless | device
// restricts the choice (default: auto, a hardware device first, then surfaceless, then a software
// device).

#include <dlfcn.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "clipray/gl/GlContext.hpp"

namespace clipray::gl {

namespace {

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  std::istringstream words(list);
  std::string word;
  while (words >> word) {
    if (word == name) return true;
  }
  return false;
}

std::string eglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    default: {
      std::ostringstream hex;
      hex << "EGL error 0x" << std::hex << error;
      return hex.str();
    }
  }
}

// One way to reach a display: a platform and its native display (a device, or nothing).
struct Candidate {
  std::string label;  // "surfaceless", "device 1 (/dev/dri/renderD128)"
  EGLenum platform = 0;
  void* nativeDisplay = nullptr;
};

class EglContext final : public GlContext {
 public:
  EglContext() {
    const char* overridePath = std::getenv("CLIPRAY_EGL_LIBRARY");
    const std::string path = overridePath && *overridePath ? overridePath : "libEGL.so.1";
    library_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library_) {
      const char* reason = dlerror();
      throw BackendError("EGL: cannot load " + path + " (" + (reason ? reason : "unknown reason") +
                         "); install Debian's libegl1 and libegl-mesa0 (harness/install-deps.sh)");
    }
    getProcAddress_ = symbol<PFNEGLGETPROCADDRESSPROC>("eglGetProcAddress");
    queryString_ = symbol<PFNEGLQUERYSTRINGPROC>("eglQueryString");
    getError_ = symbol<PFNEGLGETERRORPROC>("eglGetError");
    initialize_ = symbol<PFNEGLINITIALIZEPROC>("eglInitialize");
    bindApi_ = symbol<PFNEGLBINDAPIPROC>("eglBindAPI");
    chooseConfig_ = symbol<PFNEGLCHOOSECONFIGPROC>("eglChooseConfig");
    createContext_ = symbol<PFNEGLCREATECONTEXTPROC>("eglCreateContext");
    destroyContext_ = symbol<PFNEGLDESTROYCONTEXTPROC>("eglDestroyContext");
    makeCurrent_ = symbol<PFNEGLMAKECURRENTPROC>("eglMakeCurrent");
    sharedGetProcAddress = getProcAddress_;

    const std::vector<Candidate> candidates = findCandidates(path);
    std::string reasons;
    for (const Candidate& candidate : candidates) {
      std::string reason;
      if (tryCandidate(candidate, reason)) return;
      reasons += (reasons.empty() ? "" : "; ") + candidate.label + ": " + reason;
    }
    throw BackendError("EGL: no usable display (" + reasons + ")");
  }

  ~EglContext() override {
    makeCurrent_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    destroyContext_(display_, context_);
    // The display is not terminated: EGL displays are per process and shared, so another
    // context (a second EglContext, a test fixture) may still use it. The library stays loaded
    // for the same reasons as OSMesa's (driver threads and atexit handlers).
  }

  std::string backendName() const override { return "egl"; }

  GlLoader loader() const override {
    return [](const char* name) -> GlProc {
      return reinterpret_cast<GlProc>(sharedGetProcAddress(name));
    };
  }

 private:
  template <typename Function>
  Function symbol(const char* name) {
    void* address = dlsym(library_, name);
    if (!address) address = reinterpret_cast<void*>(getProcAddressOrNull(name));
    if (!address) {
      throw BackendError(std::string("EGL: ") + name + " missing from the loaded library");
    }
    return reinterpret_cast<Function>(address);
  }

  __eglMustCastToProperFunctionPointerType getProcAddressOrNull(const char* name) const {
    return getProcAddress_ ? getProcAddress_(name) : nullptr;
  }

  // Hardware devices first (EGL_EXT_device_enumeration), then Mesa's surfaceless platform, then
  // software devices; CLIPRAY_EGL_PLATFORM narrows the list.
  std::vector<Candidate> findCandidates(const std::string& path) {
    const char* requested = std::getenv("CLIPRAY_EGL_PLATFORM");
    const std::string only = requested && *requested ? requested : "auto";
    if (only != "auto" && only != "surfaceless" && only != "device") {
      throw BackendError("EGL: CLIPRAY_EGL_PLATFORM: unknown value \"" + only +
                         "\"; expected one of: auto, surfaceless, device");
    }
    const char* clientExtensions = queryString_(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!clientExtensions) {
      throw BackendError("EGL: no usable display: " + path +
                         " offers no client extensions (EGL_EXT_client_extensions); EGL 1.5 or "
                         "EGL_EXT_platform_base is required");
    }
    // eglGetPlatformDisplay is EGL 1.5; eglGetPlatformDisplayEXT is the extension's spelling.
    getPlatformDisplay_ =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYPROC>(dlsym(library_, "eglGetPlatformDisplay"));
    if (!getPlatformDisplay_ && hasExtension(clientExtensions, "EGL_EXT_platform_base")) {
      getPlatformDisplayExt_ = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
          getProcAddressOrNull("eglGetPlatformDisplayEXT"));
    }
    if (!getPlatformDisplay_ && !getPlatformDisplayExt_) {
      throw BackendError("EGL: " + path +
                         " has neither eglGetPlatformDisplay (EGL 1.5) nor EGL_EXT_platform_base");
    }

    std::vector<Candidate> hardware, software;
    const bool devicePlatform = hasExtension(clientExtensions, "EGL_EXT_platform_device") &&
                                (hasExtension(clientExtensions, "EGL_EXT_device_enumeration") ||
                                 hasExtension(clientExtensions, "EGL_EXT_device_base"));
    const auto queryDevices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(getProcAddressOrNull("eglQueryDevicesEXT"));
    const auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        getProcAddressOrNull("eglQueryDeviceStringEXT"));
    if (devicePlatform && queryDevices && queryDeviceString && only != "surfaceless") {
      EGLint count = 0;
      if (queryDevices(0, nullptr, &count) && count > 0) {
        std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
        queryDevices(count, devices.data(), &count);
        devices.resize(static_cast<std::size_t>(count));
        for (std::size_t k = 0; k < devices.size(); ++k) {
          const char* extensions = queryDeviceString(devices[k], EGL_EXTENSIONS);
          const bool isSoftware = hasExtension(extensions, "EGL_MESA_device_software");
          std::string label = "device " + std::to_string(k);
          const char* file = hasExtension(extensions, "EGL_EXT_device_drm")
                                 ? queryDeviceString(devices[k], EGL_DRM_DEVICE_FILE_EXT)
                                 : nullptr;
          if (file) label += std::string(" (") + file + ")";
          if (isSoftware) label += " (software)";
          (isSoftware ? software : hardware)
              .push_back({label, EGL_PLATFORM_DEVICE_EXT, devices[k]});
        }
      }
    }
    std::vector<Candidate> candidates = hardware;
    if (only != "device") {
      if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
        candidates.push_back({"surfaceless", EGL_PLATFORM_SURFACELESS_MESA, nullptr});
      } else if (only == "surfaceless") {
        throw BackendError("EGL: no usable display: " + path +
                           " does not offer the surfaceless platform "
                           "(EGL_MESA_platform_surfaceless) that CLIPRAY_EGL_PLATFORM asks for");
      }
    }
    candidates.insert(candidates.end(), software.begin(), software.end());
    if (candidates.empty()) {
      throw BackendError("EGL: no usable display: " + path +
                         " offers neither the surfaceless platform (EGL_MESA_platform_surfaceless)"
                         " nor a device (EGL_EXT_platform_device); install Mesa's libegl-mesa0 or a"
                         " GPU driver's EGL vendor library");
    }
    return candidates;
  }

  bool tryCandidate(const Candidate& candidate, std::string& reason) {
    const EGLDisplay display =
        getPlatformDisplay_
            ? getPlatformDisplay_(candidate.platform, candidate.nativeDisplay, nullptr)
            : getPlatformDisplayExt_(candidate.platform, candidate.nativeDisplay, nullptr);
    if (display == EGL_NO_DISPLAY) {
      reason = "eglGetPlatformDisplay failed (" + eglErrorName(getError_()) + ")";
      return false;
    }
    EGLint major = 0, minor = 0;
    if (!initialize_(display, &major, &minor)) {
      reason = "eglInitialize failed (" + eglErrorName(getError_()) + ")";
      return false;
    }
    const char* extensions = queryString_(display, EGL_EXTENSIONS);
    if (!hasExtension(extensions, "EGL_KHR_surfaceless_context")) {
      reason = "no EGL_KHR_surfaceless_context";
      return false;
    }
    if (major * 10 + minor < 15 && !hasExtension(extensions, "EGL_KHR_create_context")) {
      reason = "EGL " + std::to_string(major) + "." + std::to_string(minor) +
               " without EGL_KHR_create_context cannot ask for a core profile";
      return false;
    }
    if (!bindApi_(EGL_OPENGL_API)) {
      reason = "eglBindAPI(EGL_OPENGL_API) failed (" + eglErrorName(getError_()) + ")";
      return false;
    }
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
      const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint count = 0;
      if (!chooseConfig_(display, configAttributes, &config, 1, &count) || count < 1) {
        reason = "no config with EGL_OPENGL_BIT (" + eglErrorName(getError_()) + ")";
        return false;
      }
    }
    // EGL 1.5 / EGL_KHR_create_context share these enum values.
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        4,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        5,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    const EGLContext context = createContext_(display, config, EGL_NO_CONTEXT, contextAttributes);
    if (context == EGL_NO_CONTEXT) {
      reason = "cannot create a GL 4.5 core context (" + eglErrorName(getError_()) + ")";
      return false;
    }
    if (!makeCurrent_(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      reason = "eglMakeCurrent without a surface failed (" + eglErrorName(getError_()) + ")";
      destroyContext_(display, context);
      return false;
    }
    display_ = display;
    context_ = context;
    return true;
  }

  static inline PFNEGLGETPROCADDRESSPROC sharedGetProcAddress = nullptr;

  void* library_ = nullptr;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  PFNEGLGETPROCADDRESSPROC getProcAddress_ = nullptr;
  PFNEGLQUERYSTRINGPROC queryString_ = nullptr;
  PFNEGLGETERRORPROC getError_ = nullptr;
  PFNEGLINITIALIZEPROC initialize_ = nullptr;
  PFNEGLBINDAPIPROC bindApi_ = nullptr;
  PFNEGLCHOOSECONFIGPROC chooseConfig_ = nullptr;
  PFNEGLCREATECONTEXTPROC createContext_ = nullptr;
  PFNEGLDESTROYCONTEXTPROC destroyContext_ = nullptr;
  PFNEGLMAKECURRENTPROC makeCurrent_ = nullptr;
  PFNEGLGETPLATFORMDISPLAYPROC getPlatformDisplay_ = nullptr;
  PFNEGLGETPLATFORMDISPLAYEXTPROC getPlatformDisplayExt_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> createEglContext() {
  return std::make_unique<EglContext>();
}

}  // namespace clipray::gl

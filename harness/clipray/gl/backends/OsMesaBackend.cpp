// OSMesa backend: a headless GL 4.5 core context on Mesa's llvmpipe. libOSMesa is opened with
// dlopen so that its absence is a clear "OSMesa: ..." error (exit 2) rather than a loader failure.

#include <dlfcn.h>

#include <GL/osmesa.h>

#include <cstdlib>
#include <vector>

#include "clipray/gl/GlContext.hpp"

namespace clipray::gl {

namespace {

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext() {
    const char* overridePath = std::getenv("CLIPRAY_OSMESA_LIBRARY");
    const char* path = overridePath && *overridePath ? overridePath : "libOSMesa.so.8";
    library_ = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!library_) {
      const char* reason = dlerror();
      throw BackendError(std::string("OSMesa: cannot load ") + path + " (" +
                         (reason ? reason : "unknown reason") +
                         "); install Debian's libosmesa6 (harness/install-deps.sh)");
    }
    createContextAttribs_ =
        symbol<decltype(&OSMesaCreateContextAttribs)>("OSMesaCreateContextAttribs");
    makeCurrent_ = symbol<decltype(&OSMesaMakeCurrent)>("OSMesaMakeCurrent");
    destroyContext_ = symbol<decltype(&OSMesaDestroyContext)>("OSMesaDestroyContext");
    getProcAddress_ = symbol<decltype(&OSMesaGetProcAddress)>("OSMesaGetProcAddress");
    sharedGetProcAddress = getProcAddress_;

    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              4,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              5,
                              0};
    context_ = createContextAttribs_(attributes, nullptr);
    if (!context_) {
      dlclose(library_);
      throw BackendError(
          "OSMesa: cannot create a GL 4.5 core context (Mesa too old, or built without llvmpipe?)");
    }
    // OSMesa needs a client buffer to be current; clipray renders into FBOs, so 16x16 will do.
    buffer_.assign(16 * 16 * 4, 0);
    if (!makeCurrent_(context_, buffer_.data(), GL_UNSIGNED_BYTE, 16, 16)) {
      destroyContext_(context_);
      dlclose(library_);
      throw BackendError("OSMesa: OSMesaMakeCurrent failed");
    }
  }

  ~OsMesaContext() override {
    destroyContext_(context_);
    // The library stays loaded: llvmpipe's threads and atexit handlers may still refer to it.
  }

  std::string backendName() const override { return "osmesa"; }

  GlLoader loader() const override {
    return [](const char* name) -> GlProc { return sharedGetProcAddress(name); };
  }

 private:
  template <typename Function>
  Function symbol(const char* name) {
    void* address = dlsym(library_, name);
    if (!address) {
      dlclose(library_);
      throw BackendError(std::string("OSMesa: ") + name + " missing from the loaded library");
    }
    return reinterpret_cast<Function>(address);
  }

  static inline decltype(&OSMesaGetProcAddress) sharedGetProcAddress = nullptr;

  void* library_ = nullptr;
  OSMesaContext context_ = nullptr;
  std::vector<unsigned char> buffer_;
  decltype(&OSMesaCreateContextAttribs) createContextAttribs_ = nullptr;
  decltype(&OSMesaMakeCurrent) makeCurrent_ = nullptr;
  decltype(&OSMesaDestroyContext) destroyContext_ = nullptr;
  decltype(&OSMesaGetProcAddress) getProcAddress_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> createOsMesaContext() {
  return std::make_unique<OsMesaContext>();
}

}  // namespace clipray::gl

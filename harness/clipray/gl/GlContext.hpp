#pragma once
// A current GL 4.5 core context from one of the backends (one file each under backends/).
// This header includes no GL headers: the loader is passed to glad by the renderer.

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace clipray::gl {

// glad's GLADloadfunc, spelled without including glad.
using GlProc = void (*)();
using GlLoader = GlProc (*)(const char* name);

// A backend could not give us a usable context ("OSMesa: ..."). The CLI exits with status 2.
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual std::string backendName() const = 0;  // "osmesa", "egl"
  virtual GlLoader loader() const = 0;          // valid while the context lives
};

// OSMesa (Mesa llvmpipe, headless). The library is loaded at run time (libOSMesa.so.8, or the
// path in CLIPRAY_OSMESA_LIBRARY) so a machine without it gets a message, not a loader error.
std::unique_ptr<GlContext> createOsMesaContext();

// EGL without a surface (libEGL.so.1, or the path in CLIPRAY_EGL_LIBRARY, loaded at run time): the
// device platform on a GPU driver's device when one is offered, else Mesa's surfaceless platform.
// CLIPRAY_EGL_PLATFORM = surfaceless | device restricts the choice.
std::unique_ptr<GlContext> createEglContext();

// By name: "osmesa", "egl". Throws BackendError for unknown names, listing the known ones.
std::unique_ptr<GlContext> createContext(std::string_view backend);
std::vector<std::string> backendNames();

}  // namespace clipray::gl

#include <string>

#include "clipray/gl/GlContext.hpp"

namespace clipray::gl {

std::vector<std::string> backendNames() {
  return {"osmesa", "egl"};
}

std::unique_ptr<GlContext> createContext(std::string_view backend) {
  if (backend == "osmesa") return createOsMesaContext();
  if (backend == "egl") return createEglContext();
  std::string known;
  for (const std::string& name : backendNames()) known += (known.empty() ? "" : ", ") + name;
  throw BackendError("unknown backend \"" + std::string(backend) + "\"; expected one of: " + known);
}

}  // namespace clipray::gl

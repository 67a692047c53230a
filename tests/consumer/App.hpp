#pragma once
// "The app": what a GL project that consumes clipray has of its own, written as such a project
// would write it, with nothing from clipray. A box on a floor, a camera built with glm for
// glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), mouse picking with glm::unProjectZO from window
// coordinates with an upper-left origin on a HiDPI window, and a renderer with its own shaders.
// Each has a knob for a classic bug, so the tests can show that clipray catches it.

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

namespace app {

struct Mesh {
  std::vector<float> positions;  // x, y, z per vertex, world space
  std::vector<std::uint32_t> indices;
};

struct Window {
  int width = 400, height = 300;  // window units (the mouse's)
  double pixelRatio = 2.0;        // framebuffer pixels per window unit
  int framebufferWidth() const { return static_cast<int>(width * pixelRatio); }
  int framebufferHeight() const { return static_cast<int>(height * pixelRatio); }
};

struct Camera {
  glm::dmat4 viewFromWorld{1.0};
  glm::dmat4 clipFromView{1.0};  // built for ZERO_TO_ONE depth
  glm::ivec4 viewport{0};        // glViewport(x, y, width, height), framebuffer pixels
};

struct PickRay {
  glm::dvec3 origin{0.0}, direction{0.0};
};

enum class PickingBug { None, MouseYNotFlipped, UnprojectsNegativeOneToOne };
enum class RenderBug { None, NoClipControl, DepthFuncGreater };

struct App {
  Window window;
  Camera camera;
  Mesh floor, box;

  App();
  // The ray under the mouse at (x, y) window units, origin upper left.
  std::optional<PickRay> pick(glm::dvec2 mouse, PickingBug bug = PickingBug::None) const;
};

// GL entry points, loaded through the function the context gives (as glad or epoxy would).
using GlFunction = void (*)();
using GetProcAddress = GlFunction (*)(const char* name);
// Draws the floor and the box into the bound framebuffer with the app's shaders, writing
// firstIds[mesh] + gl_PrimitiveID to colour attachment 1 (the app's picking id buffer).
void render(const App& app, GetProcAddress getProcAddress,
            const std::vector<std::uint32_t>& firstIds, RenderBug bug = RenderBug::None);

}  // namespace app

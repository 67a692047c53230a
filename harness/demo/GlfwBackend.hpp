#pragma once
// GLFW backend: a window with a GL 4.5 core context, for the picking demo. Messages are prefixed
// "GLFW: ". This is the only place where window coordinates (GLFW cursor units, top-left origin)
// become framebuffer pixels (lower-left origin) and back: scaled by framebuffer / window size, y
// flipped once.

#include <string>

#include <glm/glm.hpp>

#include "clipray/gl/GlContext.hpp"

struct GLFWwindow;

namespace clipray::demo {

// Window and framebuffer sizes differ on high-DPI screens (and after some resizes).
struct WindowGeometry {
  glm::dvec2 windowSize{0.0};     // screen coordinates, as the cursor reports them
  glm::ivec2 framebufferSize{0};  // pixels

  glm::dvec2 scale() const;  // framebuffer pixels per window unit, per axis
  // The framebuffer pixel (lower-left origin) under a cursor position (top-left origin), clamped
  // to the framebuffer.
  glm::ivec2 pixelFromCursor(glm::dvec2 cursor) const;
  // Continuous framebuffer coordinates (lower-left origin) -> window coordinates (top-left).
  glm::dvec2 cursorFromFramebuffer(glm::dvec2 framebuffer) const;
};

class GlfwWindow final : public gl::GlContext {
 public:
  // Opens a window of windowSize screen units; throws BackendError ("GLFW: ...") when there is no
  // display or no GL 4.5 core context.
  GlfwWindow(const std::string& title, glm::ivec2 windowSize);
  ~GlfwWindow() override;
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  std::string backendName() const override { return "glfw"; }
  gl::GlLoader loader() const override;

  GLFWwindow* handle() const { return window_; }
  WindowGeometry geometry() const;
  // Asks for a new window size and waits (up to two seconds) until the window system applies it.
  void resize(glm::ivec2 windowSize);

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace clipray::demo

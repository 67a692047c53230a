#include "GlfwBackend.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace clipray::demo {

namespace {

std::string lastGlfwError() {
  const char* description = nullptr;
  const int code = glfwGetError(&description);
  if (code == GLFW_NO_ERROR) return "no error reported";
  return description ? description : "unknown GLFW error";
}

}  // namespace

glm::dvec2 WindowGeometry::scale() const {
  if (windowSize.x <= 0.0 || windowSize.y <= 0.0) return glm::dvec2(1.0);
  return glm::dvec2(framebufferSize) / windowSize;
}

glm::ivec2 WindowGeometry::pixelFromCursor(glm::dvec2 cursor) const {
  const glm::dvec2 s = scale();
  // Scale to framebuffer units, then flip y: the row counted from the top becomes the row counted
  // from the bottom. The pixel centre (+0.5) is taken by whoever builds the ray from the pixel.
  const int i = static_cast<int>(std::floor(cursor.x * s.x));
  const int rowFromTop = static_cast<int>(std::floor(cursor.y * s.y));
  const int j = framebufferSize.y - 1 - rowFromTop;
  return {std::clamp(i, 0, std::max(framebufferSize.x - 1, 0)),
          std::clamp(j, 0, std::max(framebufferSize.y - 1, 0))};
}

glm::dvec2 WindowGeometry::cursorFromFramebuffer(glm::dvec2 framebuffer) const {
  const glm::dvec2 s = scale();
  return {framebuffer.x / s.x, (framebufferSize.y - framebuffer.y) / s.y};
}

GlfwWindow::GlfwWindow(const std::string& title, glm::ivec2 windowSize) {
  if (!glfwInit()) {
    throw gl::BackendError("GLFW: no display available (" + lastGlfwError() +
                           "); run inside a desktop session, or under xvfb-run");
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 0);  // picking uses the renderer's FBO, not this framebuffer
  glfwWindowHint(GLFW_STENCIL_BITS, 0);
  glfwWindowHint(GLFW_SAMPLES, 0);
  window_ = glfwCreateWindow(windowSize.x, windowSize.y, title.c_str(), nullptr, nullptr);
  if (!window_) {
    const std::string reason = lastGlfwError();
    glfwTerminate();
    throw gl::BackendError("GLFW: cannot open a window with a GL 4.5 core context (" + reason +
                           ")");
  }
  glfwMakeContextCurrent(window_);
}

GlfwWindow::~GlfwWindow() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

gl::GlLoader GlfwWindow::loader() const {
  return [](const char* name) -> gl::GlProc { return glfwGetProcAddress(name); };
}

WindowGeometry GlfwWindow::geometry() const {
  int windowWidth = 0, windowHeight = 0, width = 0, height = 0;
  glfwGetWindowSize(window_, &windowWidth, &windowHeight);
  glfwGetFramebufferSize(window_, &width, &height);
  return {glm::dvec2(windowWidth, windowHeight), glm::ivec2(width, height)};
}

void GlfwWindow::resize(glm::ivec2 windowSize) {
  glfwSetWindowSize(window_, windowSize.x, windowSize.y);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < deadline) {
    glfwWaitEventsTimeout(0.02);
    const WindowGeometry g = geometry();
    if (g.windowSize == glm::dvec2(windowSize)) break;
  }
}

}  // namespace clipray::demo

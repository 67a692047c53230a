// The demo's input handling: GLFW mouse and key events (and the replayed script, which calls the
// same handlers) turned into picks, orbit / pan / zoom of the view, and setting changes.

#include <glad/gl.h>
// glad first: GLFW must not include the system GL header.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>

#include "PickDemoDetail.hpp"

namespace clipray::demo {

using detail::rotation;
using detail::translation;

// GLFW calls these with the demo in the window's user pointer; ImGui chains to them.
struct Callbacks {
  static PickDemo& demo(GLFWwindow* window) {
    return *static_cast<PickDemo*>(glfwGetWindowUserPointer(window));
  }
  static void mouseButton(GLFWwindow* window, int button, int action, int) {
    PickDemo& d = demo(window);
    if (button != GLFW_MOUSE_BUTTON_LEFT && button != GLFW_MOUSE_BUTTON_RIGHT) return;
    double x = 0, y = 0;
    glfwGetCursorPos(window, &x, &y);
    if (action == GLFW_PRESS) {
      if (ImGui::GetIO().WantCaptureMouse) return;
      d.pressedButton_ = button;
      d.pressCursor_ = d.lastCursor_ = {x, y};
      d.dragged_ = false;
    } else if (action == GLFW_RELEASE && d.pressedButton_ == button) {
      if (!d.dragged_ && button == GLFW_MOUSE_BUTTON_LEFT) d.onClick(d.pressCursor_);
      d.pressedButton_ = -1;
    }
  }
  static void cursor(GLFWwindow* window, double x, double y) {
    PickDemo& d = demo(window);
    if (d.pressedButton_ < 0) return;
    const glm::dvec2 now{x, y};
    if (!d.dragged_ && glm::distance(now, d.pressCursor_) < 3.0) return;
    d.dragged_ = true;
    d.onDrag(d.lastCursor_, now, d.pressedButton_ == GLFW_MOUSE_BUTTON_RIGHT);
    d.lastCursor_ = now;
  }
  static void scroll(GLFWwindow* window, double, double dy) {
    if (ImGui::GetIO().WantCaptureMouse) return;
    demo(window).onScroll(dy);
  }
  static void key(GLFWwindow* window, int key, int, int action, int) {
    if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
    if (key == GLFW_KEY_ESCAPE || key == GLFW_KEY_Q) {
      glfwSetWindowShouldClose(window, GLFW_TRUE);
      return;
    }
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
      const char letter = static_cast<char>('a' + (key - GLFW_KEY_A));
      if (std::string(kScriptKeys).find(letter) != std::string::npos) demo(window).onKey(letter);
    }
  }
};

void PickDemo::installInputCallbacks() {
  glfwSetWindowUserPointer(window_->handle(), this);
  glfwSetMouseButtonCallback(window_->handle(), &Callbacks::mouseButton);
  glfwSetCursorPosCallback(window_->handle(), &Callbacks::cursor);
  glfwSetScrollCallback(window_->handle(), &Callbacks::scroll);
  glfwSetKeyCallback(window_->handle(), &Callbacks::key);
}

void PickDemo::onClick(glm::dvec2 cursor) {
  const PickView view = pickView();
  const glm::ivec2 pixel = window_->geometry().pixelFromCursor(cursor);
  lastPick_ = pick(view, settings_.ray, pixel);
  pickLines_ << pickJson(*lastPick_, shownScene_, teleported_).dump() << std::endl;
}

void PickDemo::onDrag(glm::dvec2 from, glm::dvec2 to, bool rightButton) {
  if (camera_.rawClipFromWorld) return;  // a raw matrix has no view to orbit
  const glm::dvec2 delta = to - from;
  glm::dmat4 worldFromView = glm::inverse(viewFromWorld_);
  const glm::dvec3 right = glm::normalize(glm::dvec3(worldFromView[0]));
  const glm::dvec3 up = glm::normalize(glm::dvec3(worldFromView[1]));
  if (rightButton) {
    // Pan: the pivot and the camera move together by the drag, measured at the pivot's distance.
    const double distance = glm::distance(glm::dvec3(worldFromView[3]), pivot_);
    const WindowGeometry geometry = window_->geometry();
    double height = 2.0 * distance * std::tan(glm::radians(30.0));
    if (const auto* p = std::get_if<PerspectiveProjection>(&camera_.projection)) {
      height = 2.0 * distance * std::tan(glm::radians(p->fovYDegrees) / 2.0);
    } else if (const auto* o = std::get_if<OrthographicProjection>(&camera_.projection)) {
      height = o->top - o->bottom;
    }
    const glm::dvec3 move = (-delta.x * right + delta.y * up) * height / geometry.windowSize.y;
    pivot_ += move;
    worldFromView = translation(move) * worldFromView;
  } else {
    // Orbit about the pivot: yaw about world +y, pitch about the camera's right axis.
    const glm::dmat4 yaw = rotation(-delta.x * 0.008, glm::dvec3(0, 1, 0));
    const glm::dmat4 pitch = rotation(-delta.y * 0.008, right);
    glm::dmat4 turned = translation(pivot_) * yaw * pitch * translation(-pivot_) * worldFromView;
    if (std::abs(glm::normalize(glm::dvec3(turned[2])).y) > 0.995) {
      turned = translation(pivot_) * yaw * translation(-pivot_) * worldFromView;
    }
    worldFromView = turned;
  }
  viewFromWorld_ = glm::inverse(worldFromView);
  rasterDirty_ = true;
  repick();
}

void PickDemo::onScroll(double steps) {
  if (camera_.rawClipFromWorld) return;
  const glm::dmat4 worldFromView = glm::inverse(viewFromWorld_);
  const glm::dvec3 eye(worldFromView[3]);
  const double distance = glm::distance(eye, pivot_);
  if (!(distance > 0.0)) return;
  const double wanted = std::max(distance * std::pow(0.85, steps), 1e-3);
  const glm::dvec3 move = (pivot_ - eye) / distance * (distance - wanted);
  viewFromWorld_ = glm::inverse(translation(move) * worldFromView);
  rasterDirty_ = true;
  repick();
}

void PickDemo::onKey(char key) {
  switch (key) {
    case 'c': {  // no -> zo -> zo-reversed -> no, keeping the clip origin
      const DepthMode depth = settings_.mode.lowerLeft();
      const ClipOrigin origin = settings_.mode.origin;
      settings_.mode = depth == kNegativeOneToOne ? kZeroToOne
                       : depth == kZeroToOne      ? kZeroToOneReversed
                                                  : kNegativeOneToOne;
      settings_.mode.origin = origin;
      break;
    }
    case 'o':  // glClipControl's origin: lower-left <-> upper-left, keeping the depth convention
      settings_.mode.origin = settings_.mode.origin == ClipOrigin::LowerLeft
                                  ? ClipOrigin::UpperLeft
                                  : ClipOrigin::LowerLeft;
      break;
    case 'd':  // 16 -> 24 -> 32f -> 16
      settings_.depthFormat = settings_.depthFormat == DepthFormat::Unorm16 ? DepthFormat::Unorm24
                              : settings_.depthFormat == DepthFormat::Unorm24
                                  ? DepthFormat::Float32
                                  : DepthFormat::Unorm16;
      break;
    case 'm':
      settings_.ray = nextRayChoice(settings_.ray);
      break;
    case 'v':
      settings_.vertexMode = settings_.vertexMode == VertexMode::World ? VertexMode::CameraRelative
                             : settings_.vertexMode == VertexMode::CameraRelative
                                 ? VertexMode::Pretransformed
                                 : VertexMode::World;
      break;
    case 't': {
      teleported_ = !teleported_;
      shownScene_ = baseScene_;
      const glm::dvec3 offset = teleportOffset();
      for (MeshObject& object : shownScene_.objects) {
        for (glm::dvec3& p : object.worldPositions) p += offset;
      }
      break;
    }
    case 'r':
      resetView();
      break;
    case 'h':
      showHelp_ = !showHelp_;
      return;
    case 'p':
      compactPanel_ = !compactPanel_;
      return;
    default:
      return;
  }
  rasterDirty_ = true;
  repick();
}

}  // namespace clipray::demo

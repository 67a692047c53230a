#pragma once
// The picking demo: a GLFW window drawing a scene from the renderer's own id and depth buffers,
// orbit / zoom / pan, and every click picked three ways (Picking.hpp) with markers and a Dear ImGui
// panel. Keys and mouse events and the replayed script go through the same handlers.

#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "GlfwBackend.hpp"
#include "PickScript.hpp"
#include "ThreeWayPick.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::demo {

struct DemoSettings {
  DepthMode mode = kZeroToOne;  // with glClipControl's origin: C and O change it
  DepthFormat depthFormat = DepthFormat::Unorm24;
  VertexMode vertexMode = VertexMode::World;
  RayChoice ray;  // robust float
  glm::ivec2 windowSize{960, 640};
};

// "Teleport" moves the whole scene and the camera this far from the origin.
inline constexpr double kTeleportDistance = 1e5;

class PickDemo {
 public:
  // Opens the window (throws gl::BackendError "GLFW: ..." when it cannot).
  PickDemo(Scene scene, const DemoSettings& settings, std::ostream& pickLines);
  ~PickDemo();
  PickDemo(const PickDemo&) = delete;
  PickDemo& operator=(const PickDemo&) = delete;

  // Until the window closes.
  void runInteractive();
  // Replays the commands, one frame after each; then draws a few frames so the panel settles.
  void runScript(const std::vector<ScriptCommand>& commands);
  // Saves the last drawn frame (window framebuffer, panel included) as a PNG, atomically.
  void saveScreenshot(const std::string& path);

  // The handlers (GLFW callbacks and the script call these).
  void onClick(glm::dvec2 cursor);
  void onDrag(glm::dvec2 from, glm::dvec2 to, bool rightButton);
  void onScroll(double steps);
  void onKey(char key);

 private:
  struct Gpu;
  void drawFrame();
  void updateRaster();
  void repick();
  PickView pickView();  // of the current raster, redrawn first if needed
  // The demo's camera as the app draws it, under settings_.mode (its origin included):
  // clipFromWorld, and for a parametric camera the projection and view separately, and for a
  // perspective one the fov scalars too. The picks take its lower-left view
  // (lowerLeftCameraInputs).
  CameraInputs drawnCameraInputs(Viewport viewport) const;
  glm::dvec3 teleportOffset() const;
  // The camera's user clip planes in the shown scene's world (moved by the teleport offset).
  std::vector<glm::dvec4> shownClipPlanes() const;
  void drawPanel();              // PickDemoPanel.cpp
  void installInputCallbacks();  // PickDemoInput.cpp, like the handlers
  void resetView();

  Scene baseScene_;
  Scene shownScene_;  // baseScene_, moved by the teleport offset
  Camera camera_;
  DemoSettings settings_;
  std::ostream& pickLines_;
  bool teleported_ = false;
  bool showHelp_ = false;
  bool compactPanel_ = false;  // P: the panel shrinks to the pick's verdict

  glm::dmat4 viewFromWorld_{1.0};  // before the teleport offset
  glm::dvec3 pivot_{0.0};          // orbit centre, before the teleport offset

  std::unique_ptr<GlfwWindow> window_;
  std::unique_ptr<gl::Renderer> renderer_;
  std::unique_ptr<Gpu> gpu_;
  bool rasterDirty_ = true;
  RasterFrame raster_;
  CameraInputs rasterCamera_;  // the lower-left view of the camera the raster was drawn with
  std::vector<glm::dvec4> rasterClipPlanes_;  // the clip planes it was drawn with
  RasterSetup rasterSetup_;                   // how it was drawn, as the tolerance model needs it
  std::optional<SceneIntersector> intersector_;
  std::optional<PickResult> lastPick_;

  // Mouse state between press and release.
  int pressedButton_ = -1;
  glm::dvec2 pressCursor_{0.0}, lastCursor_{0.0};
  bool dragged_ = false;
  friend struct Callbacks;
};

}  // namespace clipray::demo

// The demo's app state: the window, the renderer and the display pass, the camera and settings
// the handlers change, the raster kept for picking, and the script and screenshot runs.

#include "PickDemo.hpp"

#include <glad/gl.h>
// glad first: GLFW must not include the system GL header.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#include "PickDemoDetail.hpp"
#include "clipray/InputError.hpp"
#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/report/Report.hpp"

namespace clipray::demo {

using detail::translation;

namespace {

// Draws the raster's id buffer with one flat-shaded colour per primitive: what the user sees is
// exactly what the picking buffers hold.
const char* const kDisplayVertex = R"(#version 450 core
void main() {
  // One triangle covering the viewport.
  const vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}

)";

const char* const kDisplayFragment = R"(#version 450 core
layout(binding = 0) uniform usampler2D uIds;          // R32UI primitive ids, 0: background
layout(binding = 1) uniform samplerBuffer uColours;   // shaded colour per primitive id
out vec4 fragColour;
void main() {
  const ivec2 pixel = ivec2(gl_FragCoord.xy);
  const uint id = texelFetch(uIds, pixel, 0).r;
  if (id == 0u) {
    const float t = gl_FragCoord.y / float(textureSize(uIds, 0).y);
    fragColour = vec4(mix(vec3(0.10, 0.11, 0.13), vec3(0.24, 0.27, 0.33), t), 1.0);
    return;
  }
  fragColour = vec4(texelFetch(uColours, int(id)).rgb, 1.0);
}

)";

GLuint compile(GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw gl::GlError(std::string("GL: demo display shader does not compile:\n") + log);
  }
  return shader;
}

glm::vec3 objectColour(int object) {
  static const glm::vec3 palette[] = {{0.55f, 0.60f, 0.52f}, {0.85f, 0.45f, 0.30f},
                                      {0.35f, 0.55f, 0.85f}, {0.85f, 0.75f, 0.35f},
                                      {0.65f, 0.40f, 0.75f}, {0.35f, 0.75f, 0.70f}};
  return palette[object % 6];
}

}  // namespace

PickDemo::PickDemo(Scene scene, const DemoSettings& settings, std::ostream& pickLines)
    : baseScene_(std::move(scene)), settings_(settings), pickLines_(pickLines) {
  if (baseScene_.cameras.empty()) throw InputError(baseScene_.path + ": /cameras: no camera");
  camera_ = baseScene_.cameras[0];
  shownScene_ = baseScene_;
  resetView();

  window_ = std::make_unique<GlfwWindow>("clipray-pick: " + baseScene_.name, settings.windowSize);
  renderer_ = std::make_unique<gl::Renderer>(*window_);  // loads GL (glad) through GLFW
  gpu_ = std::make_unique<Gpu>();

  const GLuint vertex = compile(GL_VERTEX_SHADER, kDisplayVertex);
  const GLuint fragment = compile(GL_FRAGMENT_SHADER, kDisplayFragment);
  gpu_->program = glCreateProgram();
  glAttachShader(gpu_->program, vertex);
  glAttachShader(gpu_->program, fragment);
  glLinkProgram(gpu_->program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  glCreateVertexArrays(1, &gpu_->vertexArray);

  // One flat-shaded colour per primitive id (a fixed light, two-sided), index 0 unused.
  const PrimitiveIdTable ids(baseScene_);
  std::vector<glm::vec4> colours(baseScene_.triangleCount() + baseScene_.primitives.size() + 1,
                                 glm::vec4(0.0f));
  // Analytic primitives: one colour each (no per-pixel normal in the id buffer), after the meshes.
  for (std::size_t p = 0; p < baseScene_.primitives.size(); ++p) {
    const int surface = static_cast<int>(baseScene_.objects.size() + p);
    colours[ids.firstAnalyticId + p] = glm::vec4(objectColour(surface) * 0.8f, 1);
  }
  const glm::dvec3 light = glm::normalize(glm::dvec3(0.4, 1.0, 0.6));
  for (std::size_t k = 0; k < baseScene_.objects.size(); ++k) {
    const MeshObject& object = baseScene_.objects[k];
    for (std::size_t t = 0; t < object.triangles.size(); ++t) {
      const glm::u32vec3 tri = object.triangles[t];
      const glm::dvec3 a = object.worldPositions[tri.x], b = object.worldPositions[tri.y],
                       c = object.worldPositions[tri.z];
      const glm::dvec3 n = glm::cross(b - a, c - a);
      const double lambert = glm::length(n) > 0 ? std::abs(glm::dot(glm::normalize(n), light)) : 0;
      const float shade = static_cast<float>(0.35 + 0.65 * lambert);
      colours[ids.firstIdOfObject[k] + t] = glm::vec4(objectColour(static_cast<int>(k)) * shade, 1);
    }
  }
  glCreateBuffers(1, &gpu_->colourBuffer);
  glNamedBufferData(gpu_->colourBuffer, static_cast<GLsizeiptr>(colours.size() * sizeof(glm::vec4)),
                    colours.data(), GL_STATIC_DRAW);
  glCreateTextures(GL_TEXTURE_BUFFER, 1, &gpu_->colourTexture);
  glTextureBuffer(gpu_->colourTexture, GL_RGBA32F, gpu_->colourBuffer);

  installInputCallbacks();

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // the demo writes no files besides the screenshot
  float xScale = 1.0f, yScale = 1.0f;
  glfwGetWindowContentScale(window_->handle(), &xScale, &yScale);
  if (xScale > 1.0f) {
    ImGui::GetStyle().ScaleAllSizes(xScale);
    io.FontGlobalScale = xScale;
  }
  ImGui_ImplGlfw_InitForOpenGL(window_->handle(), true);  // chains to the callbacks above
  ImGui_ImplOpenGL3_Init("#version 410 core");
}

PickDemo::~PickDemo() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glDeleteProgram(gpu_->program);
  glDeleteVertexArrays(1, &gpu_->vertexArray);
  glDeleteTextures(1, &gpu_->idTexture);
  glDeleteTextures(1, &gpu_->colourTexture);
  glDeleteBuffers(1, &gpu_->colourBuffer);
  renderer_.reset();
}

void PickDemo::resetView() {
  viewFromWorld_ = camera_.viewFromWorld;
  // Orbit around the point on the view axis nearest the centre of the scene's bounds.
  glm::dvec3 lower(std::numeric_limits<double>::max()), upper(-std::numeric_limits<double>::max());
  for (const MeshObject& object : baseScene_.objects) {
    for (const glm::dvec3& p : object.worldPositions) {
      lower = glm::min(lower, p);
      upper = glm::max(upper, p);
    }
  }
  const glm::dvec3 centre = lower.x <= upper.x ? (lower + upper) * 0.5 : glm::dvec3(0.0);
  const glm::dmat4 worldFromView = glm::inverse(viewFromWorld_);
  const glm::dvec3 eye(worldFromView[3]);
  const glm::dvec3 forward = -glm::normalize(glm::dvec3(worldFromView[2]));
  const double along = glm::dot(centre - eye, forward);
  pivot_ = eye + forward * (along > 0.0 ? along : glm::distance(centre, eye));
  rasterDirty_ = true;
}

glm::dvec3 PickDemo::teleportOffset() const {
  return teleported_ ? glm::dvec3(kTeleportDistance, 0.0, 0.0) : glm::dvec3(0.0);
}

std::vector<glm::dvec4> PickDemo::shownClipPlanes() const {
  // A plane keeps dot(n, p) + w >= 0. A teleported point is p + offset: the same plane through
  // the moved points has w - dot(n, offset).
  const glm::dvec3 offset = teleportOffset();
  std::vector<glm::dvec4> planes = camera_.clipPlanes;
  for (glm::dvec4& plane : planes) plane.w -= glm::dot(glm::dvec3(plane), offset);
  return planes;
}

CameraInputs PickDemo::drawnCameraInputs(Viewport viewport) const {
  // The teleport moves the camera with the scene: the view gains a translation by -offset.
  const glm::dmat4 offset = translation(-teleportOffset());
  CameraInputs inputs;
  inputs.mode = settings_.mode;
  if (camera_.rawClipFromWorld) {
    // A raw matrix: no projection, view or scalars to hand over (inverse_pv, fov_tangent: n/a).
    const glm::dmat4 clip = camera_.clipFromWorld(settings_.mode, viewport);
    inputs.clipFromWorld = teleported_ ? clip * offset : clip;
    return inputs;
  }
  Camera camera = camera_;
  camera.viewFromWorld = teleported_ ? viewFromWorld_ * offset : viewFromWorld_;
  inputs.clipFromWorld = camera.clipFromWorld(settings_.mode, viewport);  // projection * view
  Camera projection = camera_;
  projection.viewFromWorld = glm::dmat4(1.0);
  inputs.clipFromView = projection.clipFromWorld(settings_.mode, viewport);
  inputs.viewFromWorld = camera.viewFromWorld;
  if (const auto* p = std::get_if<PerspectiveProjection>(&camera_.projection)) {
    PerspectiveScalars scalars;
    scalars.fovYRadians = glm::radians(p->fovYDegrees);
    scalars.aspect = p->aspect.value_or(static_cast<double>(viewport.width) / viewport.height);
    scalars.nearDistance = p->nearDistance;
    scalars.farDistance = p->farDistance.value_or(std::numeric_limits<double>::infinity());
    // inverse(view * offset) = translation(+offset) * inverse(view), without a 4x4 inverse of
    // a matrix with 1e5 in it.
    scalars.worldFromView = translation(teleportOffset()) * glm::inverse(viewFromWorld_);
    inputs.perspective = scalars;
  }
  return inputs;
}

void PickDemo::updateRaster() {
  const WindowGeometry geometry = window_->geometry();
  const Viewport viewport{geometry.framebufferSize.x, geometry.framebufferSize.y};
  if (!rasterDirty_ && raster_.viewport == viewport) return;
  // GL draws the matrix as the app hands it, under its clip origin; glReadPixels returns the rows
  // from the bottom either way, so the picks work with the lower-left view of the same camera.
  const CameraInputs drawn = drawnCameraInputs(viewport);
  rasterCamera_ = lowerLeftCameraInputs(drawn);
  rasterClipPlanes_ = shownClipPlanes();
  const glm::dvec3 reference =
      engine::nearPlaneCentre(rasterCamera_.clipFromWorld, rasterCamera_.mode);
  gl::RenderRequest request;
  request.scene = &shownScene_;
  request.clipFromWorld = drawn.clipFromWorld;
  request.mode = settings_.mode;
  request.depthFormat = settings_.depthFormat;
  request.vertexMode = settings_.vertexMode;
  request.vertexReference = reference;
  request.viewport = viewport;
  request.depthRange = shownScene_.depthRange;
  request.clipPlanes = rasterClipPlanes_;
  raster_ = renderer_->render(request);
  // The picks cull what the picture culls: facing is decided by the matrix as drawn (GL's
  // upper-left origin negates the window-space area and so undoes its own y flip).
  intersector_.emplace(shownScene_, reference, SceneIntersector::BvhBuild::Now,
                       drawn.clipFromWorld);
  rasterSetup_.clipFromWorld = rasterCamera_.clipFromWorld;
  rasterSetup_.mode = rasterCamera_.mode;
  rasterSetup_.depthFormat = settings_.depthFormat;
  rasterSetup_.vertexMode = settings_.vertexMode;
  rasterSetup_.vertexReference = reference;
  rasterSetup_.subpixelBits = renderer_->info().subpixelBits;
  rasterSetup_.depthRange = shownScene_.depthRange;
  rasterSetup_.clipPlanes = rasterClipPlanes_;

  if (gpu_->idTextureSize != glm::ivec2(viewport.width, viewport.height)) {
    glDeleteTextures(1, &gpu_->idTexture);
    glCreateTextures(GL_TEXTURE_2D, 1, &gpu_->idTexture);
    glTextureStorage2D(gpu_->idTexture, 1, GL_R32UI, viewport.width, viewport.height);
    // Integer textures are incomplete with linear filtering.
    glTextureParameteri(gpu_->idTexture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(gpu_->idTexture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gpu_->idTextureSize = {viewport.width, viewport.height};
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(gpu_->idTexture, 0, 0, 0, viewport.width, viewport.height, GL_RED_INTEGER,
                      GL_UNSIGNED_INT, raster_.ids.data());
  rasterDirty_ = false;
}

void PickDemo::repick() {
  if (!lastPick_) return;
  updateRaster();
  const glm::ivec2 pixel = glm::min(
      lastPick_->pixel, glm::ivec2(raster_.viewport.width - 1, raster_.viewport.height - 1));
  lastPick_ = pick(pickView(), settings_.ray, pixel);
}

PickView PickDemo::pickView() {
  updateRaster();
  PickView view;
  view.scene = &shownScene_;
  view.camera = rasterCamera_;
  view.drawnOrigin = settings_.mode.origin;
  view.clipPlanes = rasterClipPlanes_;
  view.depthFormat = settings_.depthFormat;
  view.raster = &raster_;
  view.intersector = &*intersector_;
  view.setup = &rasterSetup_;
  return view;
}

void PickDemo::drawFrame() {
  const WindowGeometry geometry = window_->geometry();
  if (geometry.framebufferSize.x <= 0 || geometry.framebufferSize.y <= 0) return;  // minimised
  updateRaster();

  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, geometry.framebufferSize.x, geometry.framebufferSize.y);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);  // the renderer may have left ZO set
  glDisable(GL_DEPTH_TEST);
  glUseProgram(gpu_->program);
  glBindTextureUnit(0, gpu_->idTexture);
  glBindTextureUnit(1, gpu_->colourTexture);
  glBindVertexArray(gpu_->vertexArray);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  drawPanel();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

  // Keep the frame for --screenshot (read before the swap, from the back buffer).
  gpu_->lastFrameSize = geometry.framebufferSize;
  gpu_->lastFrame.resize(static_cast<std::size_t>(geometry.framebufferSize.x) *
                         geometry.framebufferSize.y * 4);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, geometry.framebufferSize.x, geometry.framebufferSize.y, GL_RGBA,
               GL_UNSIGNED_BYTE, gpu_->lastFrame.data());
  glfwSwapBuffers(window_->handle());
}

void PickDemo::runInteractive() {
  glfwSwapInterval(1);
  while (!glfwWindowShouldClose(window_->handle())) {
    drawFrame();
    glfwWaitEventsTimeout(0.1);
  }
}

void PickDemo::runScript(const std::vector<ScriptCommand>& commands) {
  glfwSwapInterval(0);
  drawFrame();
  for (const ScriptCommand& command : commands) {
    glfwPollEvents();
    switch (command.kind) {
      case ScriptCommand::Kind::Resize:
        window_->resize(glm::ivec2(command.a));
        break;
      case ScriptCommand::Kind::Click:
        onClick(command.a);
        break;
      case ScriptCommand::Kind::Drag:
        onDrag(command.a, command.b, command.rightButton);
        break;
      case ScriptCommand::Kind::Scroll:
        onScroll(command.steps);
        break;
      case ScriptCommand::Kind::Key:
        onKey(command.key);
        break;
    }
    drawFrame();
  }
  // Auto-sized ImGui windows take a couple of frames to settle.
  for (int k = 0; k < 3; ++k) {
    glfwPollEvents();
    drawFrame();
  }
}

void PickDemo::saveScreenshot(const std::string& path) {
  const glm::ivec2 size = gpu_->lastFrameSize;
  const std::size_t row = static_cast<std::size_t>(size.x) * 4;
  std::vector<unsigned char> topDown(gpu_->lastFrame.size());
  for (int y = 0; y < size.y; ++y) {
    std::copy_n(gpu_->lastFrame.begin() + static_cast<std::ptrdiff_t>(row * (size.y - 1 - y)), row,
                topDown.begin() + static_cast<std::ptrdiff_t>(row * y));
  }
  for (std::size_t k = 3; k < topDown.size(); k += 4) topDown[k] = 255;  // opaque
  std::string png;
  auto append = [](void* context, void* data, int count) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(count));
  };
  if (!stbi_write_png_to_func(append, &png, size.x, size.y, 4, topDown.data(),
                              static_cast<int>(row))) {
    throw std::runtime_error(path + ": cannot encode the screenshot");
  }
  writeFileAtomically(path, png);
}

}  // namespace clipray::demo

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

#include "clipray/gl/ReconcileRun.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/scene/InputError.hpp"

namespace clipray::demo {

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

glm::dmat4 translation(const glm::dvec3& t) {
  glm::dmat4 m(1.0);
  m[3] = glm::dvec4(t, 1.0);
  return m;
}

glm::dmat4 rotation(double radians, glm::dvec3 axis) {
  axis = glm::normalize(axis);
  const double c = std::cos(radians), s = std::sin(radians), k = 1.0 - c;
  const double x = axis.x, y = axis.y, z = axis.z;
  glm::dmat4 m(1.0);
  m[0] = {c + x * x * k, y * x * k + z * s, z * x * k - y * s, 0.0};
  m[1] = {x * y * k - z * s, c + y * y * k, z * y * k + x * s, 0.0};
  m[2] = {x * z * k + y * s, y * z * k - x * s, c + z * z * k, 0.0};
  return m;
}

glm::vec3 objectColour(int object) {
  static const glm::vec3 palette[] = {{0.55f, 0.60f, 0.52f}, {0.85f, 0.45f, 0.30f},
                                      {0.35f, 0.55f, 0.85f}, {0.85f, 0.75f, 0.35f},
                                      {0.65f, 0.40f, 0.75f}, {0.35f, 0.75f, 0.70f}};
  return palette[object % 6];
}

std::string formatPoint(const std::optional<glm::dvec3>& p) {
  if (!p) return "-";
  char text[128];
  std::snprintf(text, sizeof text, "(%.6f, %.6f, %.6f)", p->x, p->y, p->z);
  return text;
}

std::string objectName(const Scene& scene, int object) {
  return surfaceName(scene, object);
}

}  // namespace

struct PickDemo::Gpu {
  GLuint program = 0;
  GLuint vertexArray = 0;
  GLuint idTexture = 0;
  glm::ivec2 idTextureSize{0};
  GLuint colourBuffer = 0;
  GLuint colourTexture = 0;
  std::vector<unsigned char> lastFrame;  // RGBA of the last drawn frame, bottom row first
  glm::ivec2 lastFrameSize{0};
};

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

  glfwSetWindowUserPointer(window_->handle(), this);
  glfwSetMouseButtonCallback(window_->handle(), &Callbacks::mouseButton);
  glfwSetCursorPosCallback(window_->handle(), &Callbacks::cursor);
  glfwSetScrollCallback(window_->handle(), &Callbacks::scroll);
  glfwSetKeyCallback(window_->handle(), &Callbacks::key);

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

CameraInputs PickDemo::cameraInputs(Viewport viewport) const {
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
  rasterCamera_ = cameraInputs(viewport);
  const glm::dvec3 reference = gl::nearPlaneCentre(rasterCamera_.clipFromWorld, settings_.mode);
  gl::RenderRequest request;
  request.scene = &shownScene_;
  request.clipFromWorld = rasterCamera_.clipFromWorld;
  request.mode = settings_.mode;
  request.depthFormat = settings_.depthFormat;
  request.vertexMode = settings_.vertexMode;
  request.vertexReference = reference;
  request.viewport = viewport;
  raster_ = renderer_->render(request);
  intersector_.emplace(shownScene_, reference);

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
  const PickView view{&shownScene_, rasterCamera_, settings_.depthFormat, &raster_, &*intersector_};
  lastPick_ = pick(view, settings_.ray, pixel);
}

void PickDemo::onClick(glm::dvec2 cursor) {
  updateRaster();
  const glm::ivec2 pixel = window_->geometry().pixelFromCursor(cursor);
  const PickView view{&shownScene_, rasterCamera_, settings_.depthFormat, &raster_, &*intersector_};
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
    case 'c':  // no -> zo -> zo-reversed -> no
      settings_.mode = settings_.mode == kNegativeOneToOne ? kZeroToOne
                       : settings_.mode == kZeroToOne      ? kZeroToOneReversed
                                                           : kNegativeOneToOne;
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
    default:
      return;
  }
  rasterDirty_ = true;
  repick();
}

void PickDemo::drawPanel() {
  const WindowGeometry geometry = window_->geometry();
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.82f);
  ImGui::Begin("clipray-pick", nullptr,
               ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
  ImGui::Text("scene %s   %s", baseScene_.name.c_str(),
              teleported_ ? "TELEPORTED 1e5 from the origin" : "at the origin");
  ImGui::Text("convention %s   depth %s   vertices %s   rays %s", settings_.mode.name().c_str(),
              depthFormatName(settings_.depthFormat).c_str(),
              vertexModeName(settings_.vertexMode).c_str(), rayChoiceName(settings_.ray).c_str());
  ImGui::Text("framebuffer %dx%d   window %.0fx%.0f", geometry.framebufferSize.x,
              geometry.framebufferSize.y, geometry.windowSize.x, geometry.windowSize.y);
  ImGui::Separator();
  if (!lastPick_) {
    ImGui::TextUnformatted("left-click to pick");
  } else {
    const PickResult& p = *lastPick_;
    ImGui::Text("pixel (%d, %d)", p.pixel.x, p.pixel.y);
    if (p.rayUnavailable.empty()) {
      ImGui::TextColored(ImVec4(0.4f, 1.0f, 0.4f, 1.0f), "1 ray   %-12s %s",
                         objectName(shownScene_, p.rayObject).c_str(),
                         formatPoint(p.rayPoint).c_str());
    } else {
      ImGui::TextColored(ImVec4(0.4f, 1.0f, 0.4f, 1.0f), "1 ray   %-12s %s", "n/a",
                         p.rayUnavailable.c_str());
    }
    ImGui::TextColored(ImVec4(1.0f, 0.65f, 0.2f, 1.0f), "2 depth %-12s %s", "",
                       formatPoint(p.depthPoint).c_str());
    ImGui::TextColored(ImVec4(0.4f, 0.9f, 1.0f, 1.0f), "3 id    %s",
                       objectName(shownScene_, p.idObject).c_str());
    if (p.gapWorld) {
      ImGui::Text("gap 1-2: %.3g world units, %.3g px", *p.gapWorld, p.gapPixels.value_or(0.0));
    } else {
      ImGui::TextUnformatted("gap 1-2: -");
    }
    if (!p.rayUnavailable.empty()) {
      ImGui::TextUnformatted("1 and 3: n/a (no ray)");
    } else if (p.agree()) {
      ImGui::TextColored(ImVec4(0.4f, 1.0f, 0.4f, 1.0f), "1 and 3 agree");
    } else {
      ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.35f, 1.0f), "1 and 3 DISAGREE");
    }
  }
  ImGui::End();

  if (showHelp_) {
    ImGui::SetNextWindowPos(ImVec2(8, static_cast<float>(geometry.windowSize.y) - 8),
                            ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.7f);
    ImGui::Begin("keys", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
    ImGui::TextUnformatted(
        "left-click pick   left-drag orbit   right-drag pan   wheel zoom\n"
        "C convention (no / zo / zo-reversed)   D depth format (16 / 24 / 32f)\n"
        "M ray method: unproject_glm / two_point / inverse_pv / fov_tangent / plane_cross /\n"
        "  plane_cross_pre / full / robust (float), then robust double\n"
        "V vertex mode (world / camera-relative / pretransformed)   T teleport 1e5\n"
        "R reset view   H this help   Esc quit");
    ImGui::End();
  }

  // Markers: 1 where the ray hit, 2 where the depth readback unprojects to, 3 the picked pixel.
  if (lastPick_) {
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    const Viewport viewport = raster_.viewport;
    auto toScreen = [&](const glm::dvec2& framebuffer) {
      const glm::dvec2 w = geometry.cursorFromFramebuffer(framebuffer);
      return ImVec2(static_cast<float>(w.x), static_cast<float>(w.y));
    };
    const glm::dvec2 centre = glm::dvec2(lastPick_->pixel) + 0.5;
    const ImVec2 c = toScreen(centre);
    const float half = std::max(5.0f, static_cast<float>(0.5 / geometry.scale().x));
    draw->AddRect(ImVec2(c.x - half, c.y - half), ImVec2(c.x + half, c.y + half),
                  IM_COL32(100, 230, 255, 255), 0.0f, 0, 1.5f);
    if (lastPick_->rayPoint) {
      if (auto f =
              framebufferFromWorld(rasterCamera_.clipFromWorld, viewport, *lastPick_->rayPoint)) {
        draw->AddCircle(toScreen(*f), 9.0f, IM_COL32(100, 255, 100, 255), 20, 2.0f);
      }
    }
    if (lastPick_->depthPoint) {
      if (auto f =
              framebufferFromWorld(rasterCamera_.clipFromWorld, viewport, *lastPick_->depthPoint)) {
        const ImVec2 p = toScreen(*f);
        draw->AddLine(ImVec2(p.x - 7, p.y - 7), ImVec2(p.x + 7, p.y + 7),
                      IM_COL32(255, 165, 50, 255), 2.0f);
        draw->AddLine(ImVec2(p.x - 7, p.y + 7), ImVec2(p.x + 7, p.y - 7),
                      IM_COL32(255, 165, 50, 255), 2.0f);
      }
    }
  }
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

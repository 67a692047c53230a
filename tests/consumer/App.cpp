// The app's camera, picking and renderer (App.hpp). Nothing here knows clipray.

#include "App.hpp"

#include <GL/glcorearb.h>

#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace app {

namespace {

Mesh boxMesh(glm::vec3 min, glm::vec3 max) {
  Mesh mesh;
  for (int corner = 0; corner < 8; ++corner) {
    mesh.positions.push_back((corner & 1) ? max.x : min.x);
    mesh.positions.push_back((corner & 2) ? max.y : min.y);
    mesh.positions.push_back((corner & 4) ? max.z : min.z);
  }
  // Two triangles per face, corners numbered by their bits (x = 1, y = 2, z = 4).
  mesh.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return mesh;
}

}  // namespace

App::App(Style appStyle, bool culling, bool withSign, bool withDecal)
    : style(appStyle), cullBackFaces(culling) {
  floor.positions = {-4, 0, -4, 4, 0, -4, 4, 0, 4, -4, 0, 4};
  floor.indices = {0, 2, 1, 0, 3, 2};
  box = boxMesh({-0.7f, 0.0f, -0.7f}, {0.7f, 1.4f, 0.7f});
  if (withSign) {
    // Square to the line of sight, halfway to the box; counter-clockwise seen from the box, so
    // the camera sees its back.
    const glm::vec3 eye(3.0f, 2.5f, 4.0f), target(0.0f, 0.5f, 0.0f);
    const glm::vec3 forward = glm::normalize(target - eye);
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0.0f, 1.0f, 0.0f)));
    const glm::vec3 up = glm::cross(right, forward);
    const glm::vec3 centre = eye + 2.5f * forward + 0.3f * right;
    Mesh board;
    for (const glm::vec2 corner :
         {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
      const glm::vec3 p = centre + 0.6f * corner.x * right + 0.4f * corner.y * up;
      board.positions.insert(board.positions.end(), {p.x, p.y, p.z});
    }
    board.indices = {0, 2, 1, 0, 3, 2};
    sign = board;
  }
  if (withDecal) {
    // A poster in the plane of the box's front face, counter-clockwise seen from +z as that
    // face's triangles are: only the polygon offset decides which of the two the depth test keeps.
    Mesh poster;
    poster.positions = {-0.35f, 0.35f, 0.7f, 0.35f,  0.35f, 0.7f,
                        0.35f,  1.05f, 0.7f, -0.35f, 1.05f, 0.7f};
    poster.indices = {0, 1, 2, 0, 2, 3};
    decal = poster;
  }
  // A 3D view beside an 80-pixel side panel: the viewport starts right of it.
  const int panel = 80;
  camera.viewport = {panel, 0, window.framebufferWidth() - panel, window.framebufferHeight()};
  camera.viewFromWorld = glm::lookAtRH(glm::dvec3(3.0, 2.5, 4.0), glm::dvec3(0.0, 0.5, 0.0),
                                       glm::dvec3(0.0, 1.0, 0.0));
  camera.clipFromView = glm::perspectiveRH_ZO(
      glm::radians(50.0), double(camera.viewport.z) / camera.viewport.w, 0.1, 50.0);
  if (style == Style::ReversedDepthRange) {
    camera.clipFromView = glm::perspectiveRH_NO(
        glm::radians(50.0), double(camera.viewport.z) / camera.viewport.w, 0.1, 50.0);
  }
  // Direct3D and Vulkan count clip-space y downwards: the projection's y row negated.
  if (style == Style::Direct3D) {
    camera.clipFromView =
        glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, -1.0, 1.0)) * camera.clipFromView;
  }
}

std::optional<PickRay> App::pick(glm::dvec2 mouse, PickingBug bug) const {
  // Window units, upper-left origin, to framebuffer pixels, lower-left origin (glViewport's); the
  // Direct3D-style app keeps the upper-left origin (its viewport starts at the top, as D3D's).
  const double x = mouse.x * window.pixelRatio;
  const double y = bug == PickingBug::MouseYNotFlipped || style == Style::Direct3D
                       ? mouse.y * window.pixelRatio
                       : window.framebufferHeight() - mouse.y * window.pixelRatio;
  const glm::dvec4 viewport(camera.viewport);
  glm::dvec3 nearPoint, farPoint;
  if (bug == PickingBug::UnprojectsNegativeOneToOne || style == Style::ReversedDepthRange) {
    // glm::unProject is unProjectNO by default: window z 0 is NDC z -1, in front of the near
    // plane of a ZERO_TO_ONE projection (and the near plane of the reversed depth range's NO
    // projection, whose window depths unProject never sees).
    nearPoint = glm::unProjectNO(glm::dvec3(x, y, 0.0), camera.viewFromWorld, camera.clipFromView,
                                 viewport);
    farPoint = glm::unProjectNO(glm::dvec3(x, y, 1.0), camera.viewFromWorld, camera.clipFromView,
                                viewport);
  } else {
    nearPoint = glm::unProjectZO(glm::dvec3(x, y, 0.0), camera.viewFromWorld, camera.clipFromView,
                                 viewport);
    farPoint = glm::unProjectZO(glm::dvec3(x, y, 1.0), camera.viewFromWorld, camera.clipFromView,
                                viewport);
  }
  return PickRay{nearPoint, farPoint - nearPoint};
}

std::vector<const Mesh*> App::meshes() const {
  std::vector<const Mesh*> all = {&floor, &box};
  if (sign) all.push_back(&*sign);
  if (decal) all.push_back(&*decal);
  return all;
}

std::optional<PickedTriangle> App::pickHit(glm::dvec2 mouse, PickingBug bug) const {
  const std::optional<PickRay> ray = pick(mouse, bug);
  if (!ray) return std::nullopt;
  const bool cull = cullBackFaces && bug != PickingBug::HitsCulledFaces;
  std::optional<PickedTriangle> nearest;
  const std::vector<const Mesh*> all = meshes();
  for (std::size_t m = 0; m < all.size(); ++m) {
    const Mesh& mesh = *all[m];
    const auto vertex = [&](std::uint32_t i) {
      return glm::dvec3(mesh.positions[3 * i], mesh.positions[3 * i + 1],
                        mesh.positions[3 * i + 2]);
    };
    for (std::uint32_t k = 0; 3 * k < mesh.indices.size(); ++k) {
      const glm::dvec3 a = vertex(mesh.indices[3 * k]), b = vertex(mesh.indices[3 * k + 1]),
                       c = vertex(mesh.indices[3 * k + 2]);
      // Moller-Trumbore; a counter-clockwise triangle seen from the ray's side has det > 0.
      const glm::dvec3 e1 = b - a, e2 = c - a;
      const glm::dvec3 p = glm::cross(ray->direction, e2);
      const double det = glm::dot(e1, p);
      if (cull ? det <= 0.0 : det == 0.0) continue;
      const glm::dvec3 s = ray->origin - a;
      const double u = glm::dot(s, p) / det;
      const glm::dvec3 q = glm::cross(s, e1);
      const double v = glm::dot(ray->direction, q) / det;
      const double t = glm::dot(e2, q) / det;
      if (u < 0.0 || v < 0.0 || u + v > 1.0 || t <= 0.0 || t > 1.0) continue;
      if (!nearest || t < nearest->t) nearest = PickedTriangle{*ray, m, k, t};
    }
  }
  return nearest;
}

namespace {

struct Gl {
  PFNGLCLIPCONTROLPROC ClipControl;
  PFNGLENABLEPROC Enable;
  PFNGLDISABLEPROC Disable;
  PFNGLPOLYGONOFFSETPROC PolygonOffset;
  PFNGLCULLFACEPROC CullFace;
  PFNGLFRONTFACEPROC FrontFace;
  PFNGLDEPTHFUNCPROC DepthFunc;
  PFNGLDEPTHRANGEPROC DepthRange;
  PFNGLCLEARDEPTHPROC ClearDepth;
  PFNGLCLEARPROC Clear;
  PFNGLVIEWPORTPROC Viewport;
  PFNGLCREATESHADERPROC CreateShader;
  PFNGLSHADERSOURCEPROC ShaderSource;
  PFNGLCOMPILESHADERPROC CompileShader;
  PFNGLGETSHADERIVPROC GetShaderiv;
  PFNGLGETSHADERINFOLOGPROC GetShaderInfoLog;
  PFNGLCREATEPROGRAMPROC CreateProgram;
  PFNGLATTACHSHADERPROC AttachShader;
  PFNGLLINKPROGRAMPROC LinkProgram;
  PFNGLGETPROGRAMIVPROC GetProgramiv;
  PFNGLUSEPROGRAMPROC UseProgram;
  PFNGLDELETESHADERPROC DeleteShader;
  PFNGLDELETEPROGRAMPROC DeleteProgram;
  PFNGLGETUNIFORMLOCATIONPROC GetUniformLocation;
  PFNGLUNIFORMMATRIX4FVPROC UniformMatrix4fv;
  PFNGLUNIFORM1UIPROC Uniform1ui;
  PFNGLGENVERTEXARRAYSPROC GenVertexArrays;
  PFNGLBINDVERTEXARRAYPROC BindVertexArray;
  PFNGLDELETEVERTEXARRAYSPROC DeleteVertexArrays;
  PFNGLGENBUFFERSPROC GenBuffers;
  PFNGLBINDBUFFERPROC BindBuffer;
  PFNGLBUFFERDATAPROC BufferData;
  PFNGLDELETEBUFFERSPROC DeleteBuffers;
  PFNGLENABLEVERTEXATTRIBARRAYPROC EnableVertexAttribArray;
  PFNGLVERTEXATTRIBPOINTERPROC VertexAttribPointer;
  PFNGLDRAWELEMENTSPROC DrawElements;

  explicit Gl(GetProcAddress load) {
    const auto get = [load](auto& function, const char* name) {
      function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(load(name));
      if (!function) throw std::runtime_error(std::string("app: no GL function ") + name);
    };
    get(ClipControl, "glClipControl");
    get(Enable, "glEnable");
    get(Disable, "glDisable");
    get(PolygonOffset, "glPolygonOffset");
    get(CullFace, "glCullFace");
    get(FrontFace, "glFrontFace");
    get(DepthFunc, "glDepthFunc");
    get(DepthRange, "glDepthRange");
    get(ClearDepth, "glClearDepth");
    get(Clear, "glClear");
    get(Viewport, "glViewport");
    get(CreateShader, "glCreateShader");
    get(ShaderSource, "glShaderSource");
    get(CompileShader, "glCompileShader");
    get(GetShaderiv, "glGetShaderiv");
    get(GetShaderInfoLog, "glGetShaderInfoLog");
    get(CreateProgram, "glCreateProgram");
    get(AttachShader, "glAttachShader");
    get(LinkProgram, "glLinkProgram");
    get(GetProgramiv, "glGetProgramiv");
    get(UseProgram, "glUseProgram");
    get(DeleteShader, "glDeleteShader");
    get(DeleteProgram, "glDeleteProgram");
    get(GetUniformLocation, "glGetUniformLocation");
    get(UniformMatrix4fv, "glUniformMatrix4fv");
    get(Uniform1ui, "glUniform1ui");
    get(GenVertexArrays, "glGenVertexArrays");
    get(BindVertexArray, "glBindVertexArray");
    get(DeleteVertexArrays, "glDeleteVertexArrays");
    get(GenBuffers, "glGenBuffers");
    get(BindBuffer, "glBindBuffer");
    get(BufferData, "glBufferData");
    get(DeleteBuffers, "glDeleteBuffers");
    get(EnableVertexAttribArray, "glEnableVertexAttribArray");
    get(VertexAttribPointer, "glVertexAttribPointer");
    get(DrawElements, "glDrawElements");
  }
};

const char* const kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat4 clipFromWorld;
void main() { gl_Position = clipFromWorld * vec4(position, 1.0); }
)";

// Colour only.
const char* const kColourShader = R"(#version 450 core
layout(location = 0) out vec4 colour;
void main() { colour = vec4(0.8, 0.7, 0.5, 1.0); }
)";

// Colour for the screen, and the picking id buffer the app reads under the mouse; with
// kFragDepthWrite, the depth passed through gl_FragDepth too (RenderBug::FragDepthWritten).
const char* const kFragmentShader = R"(#version 450 core
layout(location = 0) out vec4 colour;
layout(location = 1) out uint pickId;
uniform uint firstId;
void main() {
  colour = vec4(0.8, 0.7, 0.5, 1.0);
  pickId = firstId + uint(gl_PrimitiveID);
)";
const char* const kFragDepthWrite = "  gl_FragDepth = gl_FragCoord.z;\n";

GLuint compile(const Gl& gl, GLenum kind, const char* source) {
  const GLuint shader = gl.CreateShader(kind);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("app: shader: ") + log);
  }
  return shader;
}

}  // namespace

void render(const App& app, GetProcAddress getProcAddress,
            const std::vector<std::uint32_t>& firstIds, RenderBug bug, bool writeIds) {
  const Gl gl(getProcAddress);
  const GLuint vertex = compile(gl, GL_VERTEX_SHADER, kVertexShader);
  const std::string idShader = std::string(kFragmentShader) +
                               (bug == RenderBug::FragDepthWritten ? kFragDepthWrite : "") + "}\n";
  const GLuint fragment =
      compile(gl, GL_FRAGMENT_SHADER, writeIds ? idShader.c_str() : kColourShader);
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vertex);
  gl.AttachShader(program, fragment);
  gl.LinkProgram(program);
  gl.DeleteShader(vertex);
  gl.DeleteShader(fragment);

  // The projection is built for [0, 1] depth: tell GL so (the bug: forget to). The Direct3D-style
  // projection has y down: the origin goes to the upper left (the bug: leave it lower left).
  const bool upperLeft = app.style == Style::Direct3D && bug != RenderBug::LowerLeftOrigin;
  if (app.style == Style::ReversedDepthRange) {
    // Reversed-Z without clip control: near at window depth 1, the nearer surface the greater.
    gl.DepthRange(1.0, 0.0);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(bug == RenderBug::DepthFuncLess ? GL_LESS : GL_GREATER);
    gl.ClearDepth(0.0);
  } else if (bug != RenderBug::NoClipControl) {
    gl.ClipControl(upperLeft ? GL_UPPER_LEFT : GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  }
  gl.Viewport(app.camera.viewport.x, app.camera.viewport.y, app.camera.viewport.z,
              app.camera.viewport.w);
  if (app.style != Style::ReversedDepthRange) {
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(bug == RenderBug::DepthFuncGreater ? GL_GREATER : GL_LESS);
    gl.ClearDepth(1.0);
  }
  gl.Clear(GL_DEPTH_BUFFER_BIT);
  if (app.cullBackFaces) {
    // The meshes wind counter-clockwise seen from outside; the y-down projection reverses every
    // winding on screen, and GL decides facing there (the bug: forget that).
    gl.Enable(GL_CULL_FACE);
    gl.CullFace(GL_BACK);
    gl.FrontFace(app.style == Style::Direct3D && bug != RenderBug::FrontFaceNotFlipped ? GL_CW
                                                                                       : GL_CCW);
  }

  gl.UseProgram(program);
  const glm::mat4 clipFromWorld(app.camera.clipFromView * app.camera.viewFromWorld);
  gl.UniformMatrix4fv(gl.GetUniformLocation(program, "clipFromWorld"), 1, GL_FALSE,
                      glm::value_ptr(clipFromWorld));
  const GLint firstIdLocation = gl.GetUniformLocation(program, "firstId");
  GLuint vertexArray = 0;
  gl.GenVertexArrays(1, &vertexArray);
  gl.BindVertexArray(vertexArray);
  const std::vector<const Mesh*> meshes = app.meshes();
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    GLuint buffers[2] = {0, 0};
    gl.GenBuffers(2, buffers);
    gl.BindBuffer(GL_ARRAY_BUFFER, buffers[0]);
    gl.BufferData(GL_ARRAY_BUFFER,
                  static_cast<GLsizeiptr>(meshes[m]->positions.size() * sizeof(float)),
                  meshes[m]->positions.data(), GL_STATIC_DRAW);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[1]);
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER,
                  static_cast<GLsizeiptr>(meshes[m]->indices.size() * sizeof(std::uint32_t)),
                  meshes[m]->indices.data(), GL_STATIC_DRAW);
    gl.EnableVertexAttribArray(0);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    if (writeIds) gl.Uniform1ui(firstIdLocation, firstIds.at(m));
    const bool isDecal = app.decal && meshes[m] == &*app.decal;
    if (isDecal) {
      // Out of the face it lies on, toward the camera: the nearer surface has the smaller depth
      // under GL_LESS, the greater under GL_GREATER (the bug: keep GL_LESS's sign there).
      const double toward = bug == RenderBug::DecalOffsetNotFlipped ? -1.0 : app.decalOffset();
      gl.Enable(GL_POLYGON_OFFSET_FILL);
      gl.PolygonOffset(static_cast<float>(toward), static_cast<float>(toward));
    }
    gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(meshes[m]->indices.size()), GL_UNSIGNED_INT,
                    nullptr);
    if (isDecal) gl.Disable(GL_POLYGON_OFFSET_FILL);
    gl.DeleteBuffers(2, buffers);
  }
  gl.BindVertexArray(0);
  gl.DeleteVertexArrays(1, &vertexArray);
  gl.UseProgram(0);
  gl.DeleteProgram(program);
}

}  // namespace app

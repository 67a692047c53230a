#include "clipray/gl/Renderer.hpp"

#include <glad/gl.h>

#include "clipray/gl/DepthFormats.hpp"
#include "clipray/gl/MultisampleTarget.hpp"
#include "clipray/gl/ShaderPrograms.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/Check.hpp"
#include "clipray/util/PhaseClock.hpp"

namespace clipray::shaders {
extern const char* const raster_vert;
extern const char* const raster_vert_file;
extern const char* const raster_frag;
extern const char* const raster_frag_file;
extern const char* const log_depth_frag;
extern const char* const log_depth_frag_file;
extern const char* const camera_rays_glsl;
extern const char* const camera_rays_glsl_file;
extern const char* const primitive_frag;
extern const char* const primitive_frag_file;
}  // namespace clipray::shaders

namespace clipray::gl {

namespace {

// One mesh object's draw: its first primitive id, and where its indices and vertices start.
struct MeshDraw {
  std::uint32_t firstId;
  GLsizei indexCount;
  std::size_t indexOffset;
  GLint baseVertex;
  CullFace cull;
  FrontFace frontFace;
  glm::dvec2 depthRange;  // glDepthRange(n, f) the object is drawn with (MeshObject::depthRange)
  // The camera's clip planes, then the object's own (MeshObject::clipPlanes), in input space.
  std::vector<glm::dvec4> clipPlanes;
  std::optional<PolygonOffset> polygonOffset;  // MeshObject::polygonOffset
};

// One analytic primitive's draw: its id and kind, clipFromLocal for the shader's rays, and where
// its proxy's indices and vertices start (a full-screen proxy is a clip-space triangle).
struct PrimitiveDraw {
  std::uint32_t id;
  int kind;
  glm::dmat4 clipFromLocal;
  bool fullScreen;
  std::size_t indexOffset;
  GLint baseVertex;
};

// What a frame uploads and draws: positions (x, y, z, w as float, in the vertex mode's input
// space) and triangle indices, the mesh objects' draws and the analytic primitives' proxies'.
struct RasterGeometry {
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<MeshDraw> draws;
  std::vector<PrimitiveDraw> primitiveDraws;
};

// Vertex data as the vertex mode prescribes (the matrix row comments are in raster.vert): the
// matrix the vertex shader applies to the uploaded positions.
glm::dmat4 clipFromInputOf(const RenderRequest& request) {
  const glm::dmat4& clipFromWorld = request.clipFromWorld;
  glm::dmat4 clipFromInput(1.0);
  if (request.vertexMode == VertexMode::World) clipFromInput = clipFromWorld;
  if (request.vertexMode == VertexMode::CameraRelative) {
    glm::dmat4 worldFromRelative(1.0);
    worldFromRelative[3] = glm::dvec4(request.vertexReference, 1.0);
    clipFromInput = clipFromWorld * worldFromRelative;
  }
  return clipFromInput;
}

// World-space clip planes in the vertex mode's input space: a world-space plane P keeps
// dot(P, (p_world, 1)) >= 0, and p_world = worldFromInput * p_input, so the input-space plane is
// worldFromInput^T P (in double; the shader gets it rounded to float).
std::vector<glm::dvec4> inputClipPlanes(const RenderRequest& request,
                                        const std::vector<glm::dvec4>& worldPlanes) {
  glm::dmat4 worldFromInput(1.0);
  if (request.vertexMode == VertexMode::CameraRelative) {
    worldFromInput[3] = glm::dvec4(request.vertexReference, 1.0);
  }
  if (request.vertexMode == VertexMode::Pretransformed) {
    worldFromInput = glm::inverse(request.clipFromWorld);
  }
  std::vector<glm::dvec4> planes;
  for (const glm::dvec4& plane : worldPlanes) {
    planes.push_back(glm::transpose(worldFromInput) * plane);
  }
  return planes;
}

// The mesh objects' positions in the vertex mode's input space, their triangles and draws.
void appendMeshes(const RenderRequest& request, const PrimitiveIdTable& ids,
                  RasterGeometry& geometry) {
  const Scene& scene = *request.scene;
  const glm::dmat4& clipFromWorld = request.clipFromWorld;
  std::vector<float>& vertices = geometry.vertices;
  std::vector<std::uint32_t>& indices = geometry.indices;
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const MeshObject& object = scene.objects[k];
    const GLint baseVertex = static_cast<GLint>(vertices.size() / 4);
    for (const glm::dvec3& p : object.worldPositions) {
      glm::dvec4 input(p, 1.0);
      if (request.vertexMode == VertexMode::CameraRelative)
        input = glm::dvec4(p - request.vertexReference, 1.0);
      if (request.vertexMode == VertexMode::Pretransformed)
        input = clipFromWorld * glm::dvec4(p, 1.0);
      for (int c = 0; c < 4; ++c) vertices.push_back(static_cast<float>(input[c]));
    }
    std::vector<glm::dvec4> planes = request.clipPlanes;
    planes.insert(planes.end(), object.clipPlanes.begin(), object.clipPlanes.end());
    geometry.draws.push_back({ids.firstIdOfObject[k],
                              static_cast<GLsizei>(object.triangles.size() * 3),
                              indices.size() * sizeof(std::uint32_t), baseVertex, object.cull,
                              object.frontFace, object.depthRangeOr(request.depthRange),
                              inputClipPlanes(request, planes), object.polygonOffset});
    for (const glm::u32vec3& t : object.triangles) {
      indices.insert(indices.end(), {t.x, t.y, t.z});
    }
  }
}

// Analytic primitives: a proxy that covers each one, in its local frame. Bounded shapes get a
// box 1/16 larger than their canonical extent (flat ones a slab 1/16 thick), so the proxy's
// outline lies strictly outside the shape's and float vertex error cannot uncover a pixel the
// shape covers. The infinite plane gets a full-screen triangle in clip space instead: w = 0
// vertices would need the rasterizer's clipping to reach the horizon exactly, while the
// full-screen proxy simply asks every pixel's ray (the shader discards misses).
void appendPrimitiveProxies(const RenderRequest& request, const PrimitiveIdTable& ids,
                            RasterGeometry& geometry) {
  const Scene& scene = *request.scene;
  const glm::dmat4& clipFromWorld = request.clipFromWorld;
  std::vector<float>& vertices = geometry.vertices;
  std::vector<std::uint32_t>& indices = geometry.indices;
  constexpr std::uint32_t kBoxTriangles[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5},
                                                  {0, 4, 5}, {0, 5, 1}, {2, 3, 7}, {2, 7, 6},
                                                  {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    const AnalyticPrimitive& primitive = scene.primitives[p];
    const GLint baseVertex = static_cast<GLint>(vertices.size() / 4);
    const bool fullScreen = primitive.kind == PrimitiveKind::Plane;
    geometry.primitiveDraws.push_back({ids.firstAnalyticId + static_cast<std::uint32_t>(p),
                                       static_cast<int>(primitive.kind),
                                       clipFromWorld * primitive.worldFromLocal, fullScreen,
                                       indices.size() * sizeof(std::uint32_t), baseVertex});
    if (fullScreen) {
      vertices.insert(vertices.end(), {-1, -1, 0, 1, 3, -1, 0, 1, -1, 3, 0, 1});
      indices.insert(indices.end(), {0, 1, 2});
      continue;
    }
    const bool flat =
        primitive.kind == PrimitiveKind::Disk || primitive.kind == PrimitiveKind::Quad;
    const float extent = 1.0625f, thickness = flat ? 0.0625f : extent;
    for (int corner = 0; corner < 8; ++corner) {
      vertices.insert(vertices.end(), {corner & 1 ? extent : -extent, corner & 2 ? extent : -extent,
                                       corner & 4 ? thickness : -thickness, 1.0f});
    }
    for (const auto& triangle : kBoxTriangles) {
      indices.insert(indices.end(), {triangle[0], triangle[1], triangle[2]});
    }
  }
}

// The frame's geometry: the mesh objects first, then the primitives' proxies.
RasterGeometry rasterGeometry(const RenderRequest& request) {
  const PrimitiveIdTable ids(*request.scene);
  RasterGeometry geometry;
  appendMeshes(request, ids, geometry);
  appendPrimitiveProxies(request, ids, geometry);
  return geometry;
}

}  // namespace

std::string nameShaderSources(const std::string& log, const std::vector<std::string>& files) {
  std::string named;
  std::size_t begin = 0;
  while (begin < log.size()) {
    std::size_t end = log.find('\n', begin);
    if (end == std::string::npos) end = log.size();
    std::string line = log.substr(begin, end - begin);
    // Mesa writes "n:line(column): error: ...", others "ERROR: n:line: ..."; either way the
    // source-string number is the digits before the first colon of a "n:line" pair.
    std::size_t digits = line.find_first_of("0123456789");
    while (digits != std::string::npos) {
      const std::size_t colon = line.find_first_not_of("0123456789", digits);
      const bool startsWord = digits == 0 || line[digits - 1] == ' ';
      if (startsWord && colon != std::string::npos && colon - digits <= 6 && line[colon] == ':' &&
          colon + 1 < line.size() && std::isdigit(static_cast<unsigned char>(line[colon + 1]))) {
        const std::size_t number = std::stoul(line.substr(digits, colon - digits));
        if (number >= 1 && number <= files.size()) {
          line = line.substr(0, digits) + files[number - 1] + line.substr(colon);
        }
        break;
      }
      digits = line.find_first_of("0123456789", colon == std::string::npos ? line.size() : colon);
    }
    named += line + "\n";
    begin = end + 1;
  }
  return named;
}

struct Renderer::State {
  GLuint program = 0;
  GLint clipFromInputLocation = -1;
  GLint firstIdLocation = -1;
  GLint clipPlanesLocation = -1;
  GLint clipPlaneCountLocation = -1;
  GLuint vertexArray = 0;
  GLuint vertexBuffer = 0;
  GLuint indexBuffer = 0;
  GLuint framebuffer = 0;
  GLuint colorBuffer = 0;
  GLuint depthBuffer = 0;
  // Meshes whose shader writes a logarithmic depth (RenderRequest::logDepth): raster.vert +
  // log_depth.frag, the uniforms at the locations raster.vert and raster.frag give them, and:
  GLuint logDepthProgram = 0;
  static constexpr GLint kLogDepthConstantLocation = 10;  // raster.vert's uLogDepthConstant
  static constexpr GLint kLogDepthBufFCLocation = 12;     // log_depth.frag's
  static constexpr GLint kLogDepthReversedLocation = 13;  // log_depth.frag's
  // Analytic primitives: raster.vert on a proxy + primitive.frag (camera_rays.glsl).
  GLuint primitiveProgram = 0;
  // glPolygonOffsetClamp (GL 4.6), or its ARB / EXT name (ARB_polygon_offset_clamp,
  // EXT_polygon_offset_clamp): glad loads GL 4.5 core only. Null where the implementation has
  // none; then only offsets with clamp 0 are drawn (glPolygonOffset).
  using PolygonOffsetClampProc = void (*)(GLfloat factor, GLfloat units, GLfloat clamp);
  PolygonOffsetClampProc polygonOffsetClamp = nullptr;
  // Made on the first multisampled frame.
  std::unique_ptr<MultisampleTarget> multisample;
  struct {
    GLint clipFromInput = -1, clipFromLocal = -1, viewportSize = -1, nearNdcZ = -1, facingSign = -1,
          parallel = -1, clipMinZ = -1, kind = -1, primitiveId = -1, depthRange = -1,
          defaultDepthRange = -1;
  } primitiveUniforms;

  // The steps of a frame, in the order render takes them.
  void upload(const RasterGeometry& geometry);
  // A fresh FBO of the viewport's size with the depth format's attachment; GlError if incomplete.
  void createTarget(Viewport viewport, DepthFormat depthFormat);
  // Binds the target and sets the fixed state the run draws under: the convention's clip control
  // and depth test, no culling or blending, multisampling only for a multisample target; clears
  // ids to 0 and depth to the far value.
  void beginFrame(const RenderRequest& request, GLuint target);
  // upload, beginFrame on the target and the draws, to glFinish.
  void draw(const RenderRequest& request, GLuint target, RenderTimings* timings);
  void drawMeshes(const RasterGeometry& geometry, const glm::dmat4& clipFromInput,
                  glm::dvec2 sceneDepthRange, const std::optional<LogDepthMapping>& logDepth);
  void drawPrimitives(const RenderRequest& request, const std::vector<PrimitiveDraw>& draws);
  // Depth (GL_FLOAT) and ids of the viewport, then the default framebuffer bound again.
  RasterFrame readBack(Viewport viewport);
};

Renderer::Renderer(GlContext& context) : state_(std::make_unique<State>()) {
  const int version = gladLoadGL(context.loader());
  if (version == 0) throw BackendError(context.backendName() + ": cannot load GL entry points");
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 45) {
    throw BackendError(context.backendName() + ": GL 4.5 core is required (glClipControl), got " +
                       glString(GL_VERSION));
  }
  info_.backend = context.backendName();
  info_.vendor = glString(GL_VENDOR);
  info_.renderer = glString(GL_RENDERER);
  info_.version = glString(GL_VERSION);
  glGetIntegerv(GL_SUBPIXEL_BITS, &info_.subpixelBits);
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) >= 46 ||
      hasGlExtension("GL_ARB_polygon_offset_clamp") ||
      hasGlExtension("GL_EXT_polygon_offset_clamp")) {
    for (const char* name :
         {"glPolygonOffsetClamp", "glPolygonOffsetClampARB", "glPolygonOffsetClampEXT"}) {
      if (state_->polygonOffsetClamp) break;
      state_->polygonOffsetClamp =
          reinterpret_cast<State::PolygonOffsetClampProc>(context.loader()(name));
    }
  }
  GLint viewportDims[2] = {0, 0};
  GLint renderbufferSize = 0;
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewportDims);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbufferSize);
  maxViewport_ = {std::min(viewportDims[0], renderbufferSize),
                  std::min(viewportDims[1], renderbufferSize)};

  const ShaderFile rasterVertex{shaders::raster_vert, shaders::raster_vert_file};
  state_->program =
      buildProgram(rasterVertex, {shaders::raster_frag, shaders::raster_frag_file}, "raster");
  state_->clipFromInputLocation = glGetUniformLocation(state_->program, "uClipFromInput");
  state_->firstIdLocation = glGetUniformLocation(state_->program, "uFirstId");
  state_->clipPlanesLocation = glGetUniformLocation(state_->program, "uClipPlanes");
  state_->clipPlaneCountLocation = glGetUniformLocation(state_->program, "uClipPlaneCount");
  state_->logDepthProgram = buildProgram(
      rasterVertex, {shaders::log_depth_frag, shaders::log_depth_frag_file}, "log depth");
  // drawMeshes sets the shared uniforms at the mesh program's locations for either program.
  for (const auto& [name, location] :
       {std::pair{"uClipFromInput", state_->clipFromInputLocation},
        std::pair{"uFirstId", state_->firstIdLocation},
        std::pair{"uClipPlanes", state_->clipPlanesLocation},
        std::pair{"uClipPlaneCount", state_->clipPlaneCountLocation}}) {
    CLIPRAY_CHECK(glGetUniformLocation(state_->logDepthProgram, name) == location,
                  std::string("log_depth.frag's program has ") + name + " elsewhere");
  }

  const GLuint proxyVertex =
      compileShader(GL_VERTEX_SHADER, shaders::raster_vert, shaders::raster_vert_file);
  const GLuint primitiveFragment = compileShaderFiles(
      GL_FRAGMENT_SHADER, {{shaders::primitive_frag, shaders::primitive_frag_file},
                           {shaders::camera_rays_glsl, shaders::camera_rays_glsl_file}});
  state_->primitiveProgram = linkProgram(proxyVertex, primitiveFragment, "primitive");
  glDeleteShader(proxyVertex);
  glDeleteShader(primitiveFragment);
  auto& uniforms = state_->primitiveUniforms;
  const GLuint primitiveProgram = state_->primitiveProgram;
  uniforms.clipFromInput = glGetUniformLocation(primitiveProgram, "uClipFromInput");
  uniforms.clipFromLocal = glGetUniformLocation(primitiveProgram, "uClipFromLocal");
  uniforms.viewportSize = glGetUniformLocation(primitiveProgram, "uViewportSize");
  uniforms.nearNdcZ = glGetUniformLocation(primitiveProgram, "uNearNdcZ");
  uniforms.facingSign = glGetUniformLocation(primitiveProgram, "uFacingSign");
  uniforms.parallel = glGetUniformLocation(primitiveProgram, "uParallel");
  uniforms.clipMinZ = glGetUniformLocation(primitiveProgram, "uClipMinZ");
  uniforms.depthRange = glGetUniformLocation(primitiveProgram, "uDepthRange");
  uniforms.defaultDepthRange = glGetUniformLocation(primitiveProgram, "uDefaultDepthRange");
  uniforms.kind = glGetUniformLocation(primitiveProgram, "uKind");
  uniforms.primitiveId = glGetUniformLocation(primitiveProgram, "uPrimitiveId");

  glCreateVertexArrays(1, &state_->vertexArray);
  glCreateBuffers(1, &state_->vertexBuffer);
  glCreateBuffers(1, &state_->indexBuffer);
  glVertexArrayVertexBuffer(state_->vertexArray, 0, state_->vertexBuffer, 0, 4 * sizeof(float));
  glVertexArrayElementBuffer(state_->vertexArray, state_->indexBuffer);
  glEnableVertexArrayAttrib(state_->vertexArray, 0);
  glVertexArrayAttribFormat(state_->vertexArray, 0, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(state_->vertexArray, 0, 0);
  checkGl("renderer set-up");
}

Renderer::~Renderer() {
  glDeleteFramebuffers(1, &state_->framebuffer);
  glDeleteRenderbuffers(1, &state_->colorBuffer);
  glDeleteRenderbuffers(1, &state_->depthBuffer);
  glDeleteBuffers(1, &state_->vertexBuffer);
  glDeleteBuffers(1, &state_->indexBuffer);
  glDeleteVertexArrays(1, &state_->vertexArray);
  glDeleteProgram(state_->program);
  glDeleteProgram(state_->primitiveProgram);
  glDeleteProgram(state_->logDepthProgram);
}

void Renderer::State::upload(const RasterGeometry& geometry) {
  const std::vector<float>& vertices = geometry.vertices;
  const std::vector<std::uint32_t>& indices = geometry.indices;
  glNamedBufferData(vertexBuffer, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                    vertices.data(), GL_STREAM_DRAW);
  glNamedBufferData(indexBuffer, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                    indices.data(), GL_STREAM_DRAW);
}

void Renderer::State::createTarget(Viewport viewport, DepthFormat depthFormat) {
  // A fresh FBO per frame: the depth format and the size change between runs.
  glDeleteFramebuffers(1, &framebuffer);
  glDeleteRenderbuffers(1, &colorBuffer);
  glDeleteRenderbuffers(1, &depthBuffer);
  glCreateFramebuffers(1, &framebuffer);
  glCreateRenderbuffers(1, &colorBuffer);
  glCreateRenderbuffers(1, &depthBuffer);
  glNamedRenderbufferStorage(colorBuffer, GL_R32UI, viewport.width, viewport.height);
  glNamedRenderbufferStorage(depthBuffer, depthInternalFormat(depthFormat), viewport.width,
                             viewport.height);
  glNamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colorBuffer);
  glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthBuffer);
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04X", status);
    throw GlError(std::string("GL: framebuffer incomplete (status ") + hex + ") for depth format " +
                  depthFormatName(depthFormat));
  }
  checkGl("framebuffer set-up");
}

void Renderer::State::beginFrame(const RenderRequest& request, GLuint target) {
  const Viewport viewport = request.viewport;
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  glViewport(0, 0, viewport.width, viewport.height);
  glDepthRange(request.depthRange.x, request.depthRange.y);
  // glClipControl: where NDC y = -1 lands and which NDC z the near clip plane sits at (z_n = -1
  // or 0).
  glClipControl(request.mode.origin == ClipOrigin::UpperLeft ? GL_UPPER_LEFT : GL_LOWER_LEFT,
                request.mode.convention == DepthConvention::ZeroToOne ? GL_ZERO_TO_ONE
                                                                      : GL_NEGATIVE_ONE_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  // Reversed-Z (near -> 1, far -> 0) or a reversed depth range: the nearer surface has the
  // greater depth.
  const bool greater = nearerIsGreater(request.mode, request.depthRange);
  glDepthFunc(greater ? GL_GREATER : GL_LESS);
  glDisable(GL_CULL_FACE);
  if (request.depthClamp) {
    glEnable(GL_DEPTH_CLAMP);
  } else {
    glDisable(GL_DEPTH_CLAMP);
  }
  glDisable(GL_BLEND);
  if (request.samples > 1) {
    glEnable(GL_MULTISAMPLE);
  } else {
    glDisable(GL_MULTISAMPLE);
  }
  const GLuint clearId[4] = {0, 0, 0, 0};
  const GLfloat clearDepth = greater ? 0.0f : 1.0f;
  glClearNamedFramebufferuiv(target, GL_COLOR, 0, clearId);
  glClearNamedFramebufferfv(target, GL_DEPTH, 0, &clearDepth);
}

void Renderer::State::drawMeshes(const RasterGeometry& geometry, const glm::dmat4& clipFromInput,
                                 glm::dvec2 sceneDepthRange,
                                 const std::optional<LogDepthMapping>& logDepth) {
  glUseProgram(logDepth ? logDepthProgram : program);
  if (logDepth) {
    // As three.js sets logDepthBufFC: 2 / log2(far + 1) in double, rounded to a float uniform.
    glUniform1f(kLogDepthConstantLocation, static_cast<GLfloat>(logDepth->constant()));
    glUniform1f(kLogDepthBufFCLocation, static_cast<GLfloat>(2.0 * logDepth->scale()));
    glUniform1i(kLogDepthReversedLocation, logDepth->reversed() ? 1 : 0);
  }
  const glm::mat4 uniformMatrix(clipFromInput);  // rounded to float, as an app's uniform is
  glUniformMatrix4fv(clipFromInputLocation, 1, GL_FALSE, &uniformMatrix[0][0]);
  glBindVertexArray(vertexArray);
  std::size_t enabledPlanes = 0;  // GL_CLIP_DISTANCE0 + i enabled for i below it
  for (const MeshDraw& draw : geometry.draws) {
    if (draw.indexCount == 0) continue;
    glUniform1ui(firstIdLocation, draw.firstId);
    glDepthRange(draw.depthRange.x, draw.depthRange.y);
    const std::vector<glm::vec4> planes(draw.clipPlanes.begin(), draw.clipPlanes.end());
    glUniform1i(clipPlaneCountLocation, static_cast<GLint>(planes.size()));
    if (!planes.empty()) {
      glUniform4fv(clipPlanesLocation, static_cast<GLsizei>(planes.size()), &planes[0][0]);
    }
    for (std::size_t i = 0; i < std::max(enabledPlanes, planes.size()); ++i) {
      if (i < planes.size()) {
        glEnable(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i));
      } else {
        glDisable(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i));
      }
    }
    enabledPlanes = planes.size();
    if (draw.cull == CullFace::None) {
      glDisable(GL_CULL_FACE);
    } else {
      glEnable(GL_CULL_FACE);
      glCullFace(draw.cull == CullFace::Back ? GL_BACK : GL_FRONT);
      glFrontFace(draw.frontFace == FrontFace::Ccw ? GL_CCW : GL_CW);
    }
    if (draw.polygonOffset) {
      const PolygonOffset& o = *draw.polygonOffset;
      glEnable(GL_POLYGON_OFFSET_FILL);
      if (polygonOffsetClamp) {
        polygonOffsetClamp(static_cast<GLfloat>(o.factor), static_cast<GLfloat>(o.units),
                           static_cast<GLfloat>(o.clamp));
      } else {
        glPolygonOffset(static_cast<GLfloat>(o.factor), static_cast<GLfloat>(o.units));
      }
    } else {
      glDisable(GL_POLYGON_OFFSET_FILL);
    }
    glDrawElementsBaseVertex(GL_TRIANGLES, draw.indexCount, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(draw.indexOffset), draw.baseVertex);
  }
  glDisable(GL_CULL_FACE);            // the primitives' proxies are drawn whole
  glDisable(GL_POLYGON_OFFSET_FILL);  // the primitives write their own depth
  // The primitives' shader writes the scene's range itself; glDepthRange back to the scene's.
  glDepthRange(sceneDepthRange.x, sceneDepthRange.y);
  for (std::size_t i = 0; i < enabledPlanes; ++i) {
    glDisable(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i));
  }
}

void Renderer::State::drawPrimitives(const RenderRequest& request,
                                     const std::vector<PrimitiveDraw>& draws) {
  const Viewport viewport = request.viewport;
  const auto& uniforms = primitiveUniforms;
  glUseProgram(primitiveProgram);
  glUniform2f(uniforms.viewportSize, static_cast<float>(viewport.width),
              static_cast<float>(viewport.height));
  glUniform1f(uniforms.nearNdcZ, static_cast<float>(request.mode.nearNdcZ()));
  // The CPU rays' orientation, so that both sides agree on which pixels have a ray.
  const RobustRayGenerator rays(request.clipFromWorld, request.mode);
  glUniform1f(uniforms.facingSign, static_cast<float>(rays.facingSign()));
  glUniform1i(uniforms.parallel, rays.isParallel() ? 1 : 0);
  glUniform1f(uniforms.clipMinZ, static_cast<float>(request.mode.clipVolumeMinZ()));
  // gl_FragDepth is stored as written: the shader applies glDepthRange itself.
  glUniform2f(uniforms.depthRange, static_cast<float>(request.depthRange.x),
              static_cast<float>(request.depthRange.y));
  glUniform1i(uniforms.defaultDepthRange, request.depthRange == glm::dvec2(0.0, 1.0) ? 1 : 0);
  // The proxy must not be cut by the near or far plane where the surface inside it is not:
  // depth clamping turns that clipping off; the shader decides depth range itself.
  glEnable(GL_DEPTH_CLAMP);
  for (const PrimitiveDraw& draw : draws) {
    const glm::mat4 clipFromLocal(draw.clipFromLocal);  // rounded to float once
    const glm::mat4 clipFromProxy = draw.fullScreen ? glm::mat4(1.0f) : clipFromLocal;
    // The proxy is drawn under the run's clip origin; the rays start from gl_FragCoord, whose
    // rows count from the lower left: the shader traces the lower-left view of the same matrix
    // (its y row negated for an upper-left origin, exactly as in double).
    const glm::mat4 rayClipFromLocal(
        lowerLeftClipFromWorld(glm::dmat4(clipFromLocal), request.mode.origin));
    glUniformMatrix4fv(uniforms.clipFromLocal, 1, GL_FALSE, &rayClipFromLocal[0][0]);
    glUniformMatrix4fv(uniforms.clipFromInput, 1, GL_FALSE, &clipFromProxy[0][0]);
    glUniform1i(uniforms.kind, draw.kind);
    glUniform1ui(uniforms.primitiveId, draw.id);
    glDrawElementsBaseVertex(GL_TRIANGLES, draw.fullScreen ? 3 : 36, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(draw.indexOffset), draw.baseVertex);
  }
  glDisable(GL_DEPTH_CLAMP);
}

RasterFrame Renderer::State::readBack(Viewport viewport) {
  RasterFrame frame;
  frame.viewport = viewport;
  const std::size_t count = static_cast<std::size_t>(viewport.width) * viewport.height;
  frame.depth.resize(count);
  frame.ids.resize(count);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glNamedFramebufferReadBuffer(framebuffer, GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, viewport.width, viewport.height, GL_DEPTH_COMPONENT, GL_FLOAT,
               frame.depth.data());
  glReadPixels(0, 0, viewport.width, viewport.height, GL_RED_INTEGER, GL_UNSIGNED_INT,
               frame.ids.data());
  checkGl("readback");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return frame;
}

namespace {

// What the renderer cannot draw as asked: BackendError naming the object.
void requireDrawable(const RenderRequest& request, const GlInfo& info, bool hasOffsetClamp) {
  if (!hasOffsetClamp) {
    for (const MeshObject& object : request.scene->objects) {
      if (object.polygonOffset && object.polygonOffset->clamp != 0.0) {
        throw BackendError(info.backend + " (" + info.version +
                           ") has no glPolygonOffsetClamp (GL 4.6, ARB/EXT_polygon_offset_clamp): "
                           "object \"" +
                           object.name + "\" is drawn with a polygon offset clamp");
      }
    }
  }
}

}  // namespace

void Renderer::State::draw(const RenderRequest& request, GLuint target, RenderTimings* timings) {
  const PhaseClock rasterClock;
  const RasterGeometry geometry = rasterGeometry(request);
  upload(geometry);
  beginFrame(request, target);
  drawMeshes(geometry, clipFromInputOf(request), request.depthRange, request.logDepth);
  if (!geometry.primitiveDraws.empty()) drawPrimitives(request, geometry.primitiveDraws);
  glFinish();
  checkGl("drawing");
  if (timings) {
    timings->raster = rasterClock.wallMilliseconds();
    timings->rasterCpu = rasterClock.cpuMilliseconds();
  }
}

RasterFrame Renderer::render(const RenderRequest& request, RenderTimings* timings) {
  if (request.samples != 1) {
    throw std::invalid_argument("Renderer::render draws one sample per pixel; " +
                                std::to_string(request.samples) + " samples go to renderSamples");
  }
  requireDrawable(request, info_, state_->polygonOffsetClamp != nullptr);
  state_->createTarget(request.viewport, request.depthFormat);
  state_->draw(request, state_->framebuffer, timings);
  const PhaseClock readbackClock;
  RasterFrame frame = state_->readBack(request.viewport);
  if (timings) {
    timings->readback = readbackClock.wallMilliseconds();
    timings->readbackCpu = readbackClock.cpuMilliseconds();
  }
  return frame;
}

std::vector<int> Renderer::sampleCounts(DepthFormat depthFormat) {
  return multisampleCounts(depthInternalFormat(depthFormat));
}

std::vector<glm::dvec2> Renderer::samplePositions(DepthFormat depthFormat, int samples,
                                                  Viewport viewport) {
  const std::vector<int> offered = sampleCounts(depthFormat);
  if (std::find(offered.begin(), offered.end(), samples) == offered.end()) {
    std::string counts;
    for (const int n : offered) counts += (counts.empty() ? "" : ", ") + std::to_string(n);
    throw BackendError(info_.backend + " (" + info_.renderer + ") offers no " +
                       std::to_string(samples) + "-sample " + depthFormatName(depthFormat) +
                       " depth with R32UI ids (it offers " + (counts.empty() ? "none" : counts) +
                       ")");
  }
  if (!state_->multisample) state_->multisample = std::make_unique<MultisampleTarget>();
  state_->multisample->create(viewport, depthInternalFormat(depthFormat), samples,
                              depthFormatName(depthFormat).c_str());
  return state_->multisample->samplePositions();
}

MultisampleFrame Renderer::renderSamples(const RenderRequest& request, RenderTimings* timings) {
  if (!request.scene->primitives.empty()) {
    throw BackendError(
        "multisampling draws triangle meshes only: the scene's analytic primitives write one "
        "depth per pixel (gl_FragDepth at its centre)");
  }
  MultisampleFrame frame;
  frame.positions = samplePositions(request.depthFormat, request.samples, request.viewport);
  requireDrawable(request, info_, state_->polygonOffsetClamp != nullptr);
  MultisampleTarget& target = *state_->multisample;
  state_->draw(request, target.framebuffer(), timings);
  const PhaseClock readbackClock;
  frame.samples = target.readSamples();
  if (timings) {
    timings->readback = readbackClock.wallMilliseconds();
    timings->readbackCpu = readbackClock.cpuMilliseconds();
  }
  return frame;
}

bool hasGlExtension(std::string_view name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint k = 0; k < count; ++k) {
    const GLubyte* text = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(k));
    if (text && name == reinterpret_cast<const char*>(text)) return true;
  }
  return false;
}

}  // namespace clipray::gl

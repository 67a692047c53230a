#include "clipray/gl/AppRender.hpp"

#include <glad/gl.h>

#include "clipray/gl/DepthFormats.hpp"
#include "clipray/gl/MultisampleTarget.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "clipray/InputError.hpp"
#include "clipray/util/PhaseClock.hpp"

namespace clipray::gl {

namespace {

std::string hex(unsigned value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%04X", value);
  return text;
}

// GL's initial state for what a depth-tested draw depends on: what an app that forgets to set
// something draws with.
void resetToGlDefaults(Viewport size) {
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glDisable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDepthRange(0.0, 1.0);
  glClearDepth(1.0);
  glViewport(0, 0, size.width, size.height);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_BLEND);
  glEnable(GL_MULTISAMPLE);
  glUseProgram(0);
  glBindVertexArray(0);
}

// The frame's framebuffer objects, deleted however the app's function ends.
struct AppFramebuffer {
  GLuint framebuffer = 0, colour = 0, ids = 0, depth = 0;
  AppFramebuffer(Viewport size, DepthFormat format, bool stencil) {
    glCreateFramebuffers(1, &framebuffer);
    glCreateRenderbuffers(1, &colour);
    glCreateRenderbuffers(1, &ids);
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(colour, GL_RGBA8, size.width, size.height);
    glNamedRenderbufferStorage(ids, GL_R32UI, size.width, size.height);
    glNamedRenderbufferStorage(depth, depthInternalFormat(format, stencil), size.width,
                               size.height);
    glNamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    glNamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, ids);
    glNamedFramebufferRenderbuffer(framebuffer,
                                   stencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT,
                                   GL_RENDERBUFFER, depth);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(framebuffer, 2, buffers);
    const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      throw GlError("GL: the app's framebuffer is incomplete (status " + hex(status) +
                    ") for depth format " + depthFormatName(format));
    }
  }
  ~AppFramebuffer() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &framebuffer);
    const GLuint buffers[3] = {colour, ids, depth};
    glDeleteRenderbuffers(3, buffers);
  }
  AppFramebuffer(const AppFramebuffer&) = delete;
  AppFramebuffer& operator=(const AppFramebuffer&) = delete;
};

// The draw functions the app loads through AppFrame::getProcAddress are these: each reads the
// state the call is made with, and with one id per draw call numbers the call in the stencil
// buffer (the fragments that pass the depth test write it), before making it. State for the one
// app render at a time (renderWithApp holds the lock).
struct DrawCallRecorder {
  std::mutex lock;
  GlLoader loader = nullptr;  // the context's
  bool numberInStencil = false;
  // GL_POLYGON_OFFSET_CLAMP can be read (GL 4.6, ARB/EXT_polygon_offset_clamp): else glGet of it
  // would leave GL_INVALID_ENUM among the app's errors.
  bool offsetClampReadable = false;
  std::vector<AppDrawState> draws;
};
DrawCallRecorder drawCalls;

AppDrawState currentDrawState() {
  AppDrawState state;
  GLint value = 0;
  glGetIntegerv(GL_CLIP_ORIGIN, &value);
  state.origin = value == GL_UPPER_LEFT ? ClipOrigin::UpperLeft : ClipOrigin::LowerLeft;
  glGetIntegerv(GL_CLIP_DEPTH_MODE, &value);
  state.convention =
      value == GL_ZERO_TO_ONE ? DepthConvention::ZeroToOne : DepthConvention::NegativeOneToOne;
  GLdouble range[2] = {0.0, 1.0};
  glGetDoublev(GL_DEPTH_RANGE, range);
  state.depthRange = {range[0], range[1]};
  state.depthTest = glIsEnabled(GL_DEPTH_TEST) == GL_TRUE;
  glGetIntegerv(GL_DEPTH_FUNC, &value);
  state.depthFunc = static_cast<std::uint32_t>(value);
  if (glIsEnabled(GL_CULL_FACE) == GL_TRUE) {
    glGetIntegerv(GL_CULL_FACE_MODE, &value);
    state.cull = value == GL_BACK    ? CullFace::Back
                 : value == GL_FRONT ? CullFace::Front
                                     : CullFace::None;
    state.cullsEverything = value == GL_FRONT_AND_BACK;
  }
  glGetIntegerv(GL_FRONT_FACE, &value);
  state.frontFace = value == GL_CW ? FrontFace::Cw : FrontFace::Ccw;
  state.depthClamp = glIsEnabled(GL_DEPTH_CLAMP) == GL_TRUE;
  if (glIsEnabled(GL_POLYGON_OFFSET_FILL) == GL_TRUE) {
    GLfloat factor = 0.0f, units = 0.0f, clamp = 0.0f;
    glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &factor);
    glGetFloatv(GL_POLYGON_OFFSET_UNITS, &units);
    // GL_POLYGON_OFFSET_CLAMP (0x8E1B): not in the GL 4.5 core header glad made.
    if (drawCalls.offsetClampReadable) glGetFloatv(0x8E1B, &clamp);
    state.polygonOffset = PolygonOffset{factor, units, clamp};
  }
  return state;
}

void beforeDrawCall() {
  drawCalls.draws.push_back(currentDrawState());
  if (!drawCalls.numberInStencil) return;
  const auto calls = static_cast<unsigned>(std::min<std::size_t>(drawCalls.draws.size(), 255));
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, static_cast<GLint>(calls), 0xFF);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  glStencilMask(0xFF);
}

// The draw calls of GL 4.5 core; each forwards to the context's own function (glad's pointer).
void GLAD_API_PTR drawArrays(GLenum mode, GLint first, GLsizei count) {
  beforeDrawCall();
  glDrawArrays(mode, first, count);
}
void GLAD_API_PTR drawArraysInstanced(GLenum mode, GLint first, GLsizei count, GLsizei instances) {
  beforeDrawCall();
  glDrawArraysInstanced(mode, first, count, instances);
}
void GLAD_API_PTR drawArraysInstancedBaseInstance(GLenum mode, GLint first, GLsizei count,
                                                  GLsizei instances, GLuint baseInstance) {
  beforeDrawCall();
  glDrawArraysInstancedBaseInstance(mode, first, count, instances, baseInstance);
}
void GLAD_API_PTR drawArraysIndirect(GLenum mode, const void* indirect) {
  beforeDrawCall();
  glDrawArraysIndirect(mode, indirect);
}
void GLAD_API_PTR drawElements(GLenum mode, GLsizei count, GLenum type, const void* indices) {
  beforeDrawCall();
  glDrawElements(mode, count, type, indices);
}
void GLAD_API_PTR drawElementsBaseVertex(GLenum mode, GLsizei count, GLenum type,
                                         const void* indices, GLint baseVertex) {
  beforeDrawCall();
  glDrawElementsBaseVertex(mode, count, type, indices, baseVertex);
}
void GLAD_API_PTR drawRangeElements(GLenum mode, GLuint start, GLuint end, GLsizei count,
                                    GLenum type, const void* indices) {
  beforeDrawCall();
  glDrawRangeElements(mode, start, end, count, type, indices);
}
void GLAD_API_PTR drawRangeElementsBaseVertex(GLenum mode, GLuint start, GLuint end, GLsizei count,
                                              GLenum type, const void* indices, GLint baseVertex) {
  beforeDrawCall();
  glDrawRangeElementsBaseVertex(mode, start, end, count, type, indices, baseVertex);
}
void GLAD_API_PTR drawElementsInstanced(GLenum mode, GLsizei count, GLenum type,
                                        const void* indices, GLsizei instances) {
  beforeDrawCall();
  glDrawElementsInstanced(mode, count, type, indices, instances);
}
void GLAD_API_PTR drawElementsInstancedBaseVertex(GLenum mode, GLsizei count, GLenum type,
                                                  const void* indices, GLsizei instances,
                                                  GLint baseVertex) {
  beforeDrawCall();
  glDrawElementsInstancedBaseVertex(mode, count, type, indices, instances, baseVertex);
}
void GLAD_API_PTR drawElementsInstancedBaseInstance(GLenum mode, GLsizei count, GLenum type,
                                                    const void* indices, GLsizei instances,
                                                    GLuint baseInstance) {
  beforeDrawCall();
  glDrawElementsInstancedBaseInstance(mode, count, type, indices, instances, baseInstance);
}
void GLAD_API_PTR drawElementsInstancedBaseVertexBaseInstance(GLenum mode, GLsizei count,
                                                              GLenum type, const void* indices,
                                                              GLsizei instances, GLint baseVertex,
                                                              GLuint baseInstance) {
  beforeDrawCall();
  glDrawElementsInstancedBaseVertexBaseInstance(mode, count, type, indices, instances, baseVertex,
                                                baseInstance);
}
void GLAD_API_PTR drawElementsIndirect(GLenum mode, GLenum type, const void* indirect) {
  beforeDrawCall();
  glDrawElementsIndirect(mode, type, indirect);
}
void GLAD_API_PTR multiDrawArrays(GLenum mode, const GLint* first, const GLsizei* count,
                                  GLsizei draws) {
  beforeDrawCall();
  glMultiDrawArrays(mode, first, count, draws);
}
void GLAD_API_PTR multiDrawElements(GLenum mode, const GLsizei* count, GLenum type,
                                    const void* const* indices, GLsizei draws) {
  beforeDrawCall();
  glMultiDrawElements(mode, count, type, indices, draws);
}
void GLAD_API_PTR multiDrawElementsBaseVertex(GLenum mode, const GLsizei* count, GLenum type,
                                              const void* const* indices, GLsizei draws,
                                              const GLint* baseVertex) {
  beforeDrawCall();
  glMultiDrawElementsBaseVertex(mode, count, type, indices, draws, baseVertex);
}
void GLAD_API_PTR multiDrawArraysIndirect(GLenum mode, const void* indirect, GLsizei draws,
                                          GLsizei stride) {
  beforeDrawCall();
  glMultiDrawArraysIndirect(mode, indirect, draws, stride);
}
void GLAD_API_PTR multiDrawElementsIndirect(GLenum mode, GLenum type, const void* indirect,
                                            GLsizei draws, GLsizei stride) {
  beforeDrawCall();
  glMultiDrawElementsIndirect(mode, type, indirect, draws, stride);
}

GlProc asProc(auto function) {
  return reinterpret_cast<GlProc>(function);
}

GlProc recordingLoader(const char* name) {
  static const std::map<std::string_view, GlProc> wrapped = {
      {"glDrawArrays", asProc(&drawArrays)},
      {"glDrawArraysInstanced", asProc(&drawArraysInstanced)},
      {"glDrawArraysInstancedBaseInstance", asProc(&drawArraysInstancedBaseInstance)},
      {"glDrawArraysIndirect", asProc(&drawArraysIndirect)},
      {"glDrawElements", asProc(&drawElements)},
      {"glDrawElementsBaseVertex", asProc(&drawElementsBaseVertex)},
      {"glDrawRangeElements", asProc(&drawRangeElements)},
      {"glDrawRangeElementsBaseVertex", asProc(&drawRangeElementsBaseVertex)},
      {"glDrawElementsInstanced", asProc(&drawElementsInstanced)},
      {"glDrawElementsInstancedBaseVertex", asProc(&drawElementsInstancedBaseVertex)},
      {"glDrawElementsInstancedBaseInstance", asProc(&drawElementsInstancedBaseInstance)},
      {"glDrawElementsInstancedBaseVertexBaseInstance",
       asProc(&drawElementsInstancedBaseVertexBaseInstance)},
      {"glDrawElementsIndirect", asProc(&drawElementsIndirect)},
      {"glMultiDrawArrays", asProc(&multiDrawArrays)},
      {"glMultiDrawElements", asProc(&multiDrawElements)},
      {"glMultiDrawElementsBaseVertex", asProc(&multiDrawElementsBaseVertex)},
      {"glMultiDrawArraysIndirect", asProc(&multiDrawArraysIndirect)},
      {"glMultiDrawElementsIndirect", asProc(&multiDrawElementsIndirect)},
  };
  const auto found = wrapped.find(name);
  return found != wrapped.end() ? found->second : drawCalls.loader(name);
}

// Not a clear value any convention uses: a frame whose depth the app never cleared shows it.
constexpr GLfloat unclearedDepth = 0.5f;

// Ids the scene cannot have, or none where the app drew: GlError naming them.
void checkAppIds(const RasterFrame& raster, const Scene& scene) {
  const Viewport size = raster.viewport;
  const std::size_t count = raster.ids.size();
  const PrimitiveIdTable table(scene);
  const std::uint64_t lastId =
      std::uint64_t{table.firstAnalyticId} + table.analyticCount - 1;  // 0 for an empty scene
  bool anyId = false, anyDrawn = false;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t id = raster.ids[i];
    anyId = anyId || id != 0;
    const float depth = raster.depth[i];
    anyDrawn = anyDrawn || (depth != 0.0f && depth != 1.0f && depth != unclearedDepth);
    if (id > lastId) {
      const int x = static_cast<int>(i % static_cast<std::size_t>(size.width));
      const int y = static_cast<int>(i / static_cast<std::size_t>(size.width));
      throw GlError("the app's render function wrote id " + std::to_string(id) + " at pixel (" +
                    std::to_string(x) + ", " + std::to_string(y) + ") of colour attachment 1; " +
                    "the scene's ids end at " + std::to_string(lastId) +
                    " (write firstId(mesh) + gl_PrimitiveID, and clear depth only: a colour "
                    "clear of the integer attachment is undefined)");
    }
  }
  if (!anyId && anyDrawn) {
    throw GlError(
        "the app's render function drew depth but wrote no ids to colour attachment 1 "
        "(layout(location = 1) out uint: firstId(mesh) + gl_PrimitiveID; or reconcile "
        "with one id per draw call, AppIds::PerDrawCall)");
  }
}

}  // namespace

AppRaster renderWithApp(GlContext& context, const AppRenderFunction& render, AppFrame frame,
                        AppIds ids, const Scene& scene, RenderTimings* timings) {
  const bool perDrawCall = ids == AppIds::PerDrawCall;
  if (perDrawCall && frame.depthFormat == DepthFormat::Unorm16) {
    throw InputError(
        "ReconcileOptions: depthFormats: one id per draw call (AppIds::PerDrawCall) "
        "counts draws in the stencil buffer, which GL pairs with depth formats 24 "
        "and 32f only; got 16");
  }
  const bool multisampled = frame.samples > 1;
  if (perDrawCall && multisampled) {
    throw InputError("ReconcileOptions: samples " + std::to_string(frame.samples) +
                     ": one id per draw call (AppIds::PerDrawCall) is read from the stencil "
                     "buffer, one value per pixel; a multisampled app frame needs its ids "
                     "written per fragment (AppIds::Written)");
  }
  // One of the two is made: the single-sample framebuffer, or multisample textures read back one
  // sample at a time (MultisampleTarget).
  std::optional<AppFramebuffer> singleSample;
  std::optional<MultisampleTarget> multisample;
  GLuint framebuffer = 0;
  if (multisampled) {
    multisample.emplace();
    multisample->create(frame.size, depthInternalFormat(frame.depthFormat, false), frame.samples,
                        depthFormatName(frame.depthFormat).c_str(),
                        MultisampleTarget::Attachments::AppColourAndIds);
    framebuffer = multisample->framebuffer();
  } else {
    singleSample.emplace(frame.size, frame.depthFormat, perDrawCall);
    framebuffer = singleSample->framebuffer;
  }
  const Viewport size{frame.viewport.z, frame.viewport.w};  // the region compared
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  AppRaster result;
  if (multisampled) result.samplePositions = multisample->samplePositions();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  const GLuint zeroIds[4] = {0, 0, 0, 0};
  const GLfloat zeroColour[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, zeroColour);
  glClearNamedFramebufferuiv(framebuffer, GL_COLOR, 1, zeroIds);
  if (perDrawCall) {
    glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, unclearedDepth, 0);
  } else {
    glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &unclearedDepth);
  }
  resetToGlDefaults(frame.size);
  glDisable(GL_STENCIL_TEST);
  while (glGetError() != GL_NO_ERROR) {
  }

  const std::lock_guard<std::mutex> recordingDraws(drawCalls.lock);
  drawCalls.loader = context.loader();
  drawCalls.numberInStencil = perDrawCall;
  {
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    drawCalls.offsetClampReadable = major * 10 + minor >= 46 ||
                                    hasGlExtension("GL_ARB_polygon_offset_clamp") ||
                                    hasGlExtension("GL_EXT_polygon_offset_clamp");
  }
  drawCalls.draws.clear();
  frame.getProcAddress = &recordingLoader;
  frame.framebuffer = framebuffer;
  const PhaseClock rasterClock;
  render(frame);
  glFinish();
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
    throw GlError("GL: the app's render function left GL error " + hex(error));
  }
  GLint bound = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
  if (static_cast<GLuint>(bound) != framebuffer) {
    throw GlError("GL: the app's render function bound framebuffer " + std::to_string(bound) +
                  " and left it bound; it must draw into AppFrame::framebuffer (" +
                  std::to_string(framebuffer) + ") and leave it bound");
  }
  if (perDrawCall && drawCalls.draws.size() > std::min<std::size_t>(scene.objects.size(), 255)) {
    throw GlError(
        "the app's render function made " + std::to_string(drawCalls.draws.size()) +
        " draw calls; with one id per draw call, call k draws mesh k, and the scene has " +
        std::to_string(scene.objects.size()) + " meshes (at most 255)");
  }
  if (timings) {
    timings->raster = rasterClock.wallMilliseconds();
    timings->rasterCpu = rasterClock.cpuMilliseconds();
  }

  const PhaseClock readbackClock;
  result.draws = std::move(drawCalls.draws);
  drawCalls.draws.clear();
  if (multisampled) {
    result.samples = multisample->readSamples(frame.viewport);
    if (timings) {
      timings->readback = readbackClock.wallMilliseconds();
      timings->readbackCpu = readbackClock.cpuMilliseconds();
    }
    for (const RasterFrame& sample : result.samples) checkAppIds(sample, scene);
    result.frame = result.samples.front();
    return result;
  }
  RasterFrame& raster = result.frame;
  raster.viewport = size;
  const std::size_t count = static_cast<std::size_t>(size.width) * size.height;
  raster.depth.resize(count);
  raster.ids.resize(count);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glPixelStorei(GL_PACK_SKIP_ROWS, 0);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glNamedFramebufferReadBuffer(framebuffer, GL_COLOR_ATTACHMENT1);
  const int x0 = frame.viewport.x, y0 = frame.viewport.y;
  glReadPixels(x0, y0, size.width, size.height, GL_DEPTH_COMPONENT, GL_FLOAT, raster.depth.data());
  if (perDrawCall) {
    result.meshOfPixel.resize(count);
    glReadPixels(x0, y0, size.width, size.height, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE,
                 result.meshOfPixel.data());
  } else {
    glReadPixels(x0, y0, size.width, size.height, GL_RED_INTEGER, GL_UNSIGNED_INT,
                 raster.ids.data());
  }
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
    throw GlError("GL: reading back the app's frame failed with GL error " + hex(error));
  }
  if (timings) {
    timings->readback = readbackClock.wallMilliseconds();
    timings->readbackCpu = readbackClock.cpuMilliseconds();
  }
  if (perDrawCall) return result;

  checkAppIds(raster, scene);
  return result;
}

}  // namespace clipray::gl

#include "clipray/gl/AppRender.hpp"

#include <glad/gl.h>

#include <cstdio>
#include <string>

#include "clipray/util/PhaseClock.hpp"

namespace clipray::gl {

namespace {

GLenum depthInternalFormat(DepthFormat format) {
  switch (format) {
    case DepthFormat::Unorm16:
      return GL_DEPTH_COMPONENT16;
    case DepthFormat::Unorm24:
      return GL_DEPTH_COMPONENT24;
    case DepthFormat::Float32:
      return GL_DEPTH_COMPONENT32F;
  }
  return GL_DEPTH_COMPONENT32F;
}

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
  glUseProgram(0);
  glBindVertexArray(0);
}

// The frame's framebuffer objects, deleted however the app's function ends.
struct AppFramebuffer {
  GLuint framebuffer = 0, colour = 0, ids = 0, depth = 0;
  AppFramebuffer(Viewport size, DepthFormat format) {
    glCreateFramebuffers(1, &framebuffer);
    glCreateRenderbuffers(1, &colour);
    glCreateRenderbuffers(1, &ids);
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(colour, GL_RGBA8, size.width, size.height);
    glNamedRenderbufferStorage(ids, GL_R32UI, size.width, size.height);
    glNamedRenderbufferStorage(depth, depthInternalFormat(format), size.width, size.height);
    glNamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    glNamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, ids);
    glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
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

}  // namespace

RasterFrame renderWithApp(GlContext& context, const AppRenderFunction& render, AppFrame frame,
                          const Scene& scene, RenderTimings* timings) {
  AppFramebuffer target(frame.size, frame.depthFormat);
  const Viewport size{frame.viewport.z, frame.viewport.w};  // the region compared
  glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
  const GLuint zeroIds[4] = {0, 0, 0, 0};
  const GLfloat zeroColour[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  // Not a clear value any convention uses: a frame whose depth the app never cleared shows it.
  const GLfloat unclearedDepth = 0.5f;
  glClearNamedFramebufferfv(target.framebuffer, GL_COLOR, 0, zeroColour);
  glClearNamedFramebufferuiv(target.framebuffer, GL_COLOR, 1, zeroIds);
  glClearNamedFramebufferfv(target.framebuffer, GL_DEPTH, 0, &unclearedDepth);
  resetToGlDefaults(frame.size);
  while (glGetError() != GL_NO_ERROR) {
  }

  frame.getProcAddress = context.loader();  // GlLoader and GlGetProcAddress are one type
  frame.framebuffer = target.framebuffer;
  const PhaseClock rasterClock;
  render(frame);
  glFinish();
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
    throw GlError("GL: the app's render function left GL error " + hex(error));
  }
  GLint bound = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
  if (static_cast<GLuint>(bound) != target.framebuffer) {
    throw GlError("GL: the app's render function bound framebuffer " + std::to_string(bound) +
                  " and left it bound; it must draw into AppFrame::framebuffer (" +
                  std::to_string(target.framebuffer) + ") and leave it bound");
  }
  if (timings) {
    timings->raster = rasterClock.wallMilliseconds();
    timings->rasterCpu = rasterClock.cpuMilliseconds();
  }

  const PhaseClock readbackClock;
  RasterFrame raster;
  raster.viewport = size;
  const std::size_t count = static_cast<std::size_t>(size.width) * size.height;
  raster.depth.resize(count);
  raster.ids.resize(count);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glPixelStorei(GL_PACK_SKIP_ROWS, 0);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, target.framebuffer);
  glNamedFramebufferReadBuffer(target.framebuffer, GL_COLOR_ATTACHMENT1);
  const int x0 = frame.viewport.x, y0 = frame.viewport.y;
  glReadPixels(x0, y0, size.width, size.height, GL_DEPTH_COMPONENT, GL_FLOAT, raster.depth.data());
  glReadPixels(x0, y0, size.width, size.height, GL_RED_INTEGER, GL_UNSIGNED_INT, raster.ids.data());
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
    throw GlError("GL: reading back the app's frame failed with GL error " + hex(error));
  }
  if (timings) {
    timings->readback = readbackClock.wallMilliseconds();
    timings->readbackCpu = readbackClock.cpuMilliseconds();
  }

  // Ids the scene cannot have, or none where the app drew.
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
        "(layout(location = 1) out uint: firstId(mesh) + gl_PrimitiveID)");
  }
  return raster;
}

}  // namespace clipray::gl

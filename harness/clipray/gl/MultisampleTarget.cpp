#include "clipray/gl/MultisampleTarget.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "clipray/gl/Renderer.hpp"
#include "clipray/gl/ShaderPrograms.hpp"

namespace clipray::shaders {
extern const char* const sample_fetch_vert;
extern const char* const sample_fetch_vert_file;
extern const char* const sample_fetch_frag;
extern const char* const sample_fetch_frag_file;
}  // namespace clipray::shaders

namespace clipray::gl {

namespace {

std::vector<int> samplesOf(GLenum internalFormat) {
  GLint count = 0;
  glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, internalFormat, GL_NUM_SAMPLE_COUNTS, 1, &count);
  std::vector<GLint> samples(static_cast<std::size_t>(std::max(count, 0)));
  if (count > 0) {
    glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, internalFormat, GL_SAMPLES, count,
                          samples.data());
  }
  return {samples.begin(), samples.end()};
}

void requireComplete(GLuint framebuffer, const std::string& what) {
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04X", status);
    throw GlError("GL: framebuffer incomplete (status " + std::string(hex) + ") for " + what);
  }
}

}  // namespace

std::vector<int> multisampleCounts(GLenum depthInternalFormat) {
  std::vector<int> depth = samplesOf(depthInternalFormat);
  std::vector<int> ids = samplesOf(GL_R32UI);
  std::sort(depth.begin(), depth.end());
  std::sort(ids.begin(), ids.end());
  std::vector<int> both;
  std::set_intersection(depth.begin(), depth.end(), ids.begin(), ids.end(),
                        std::back_inserter(both));
  std::erase_if(both, [](int n) { return n <= 1; });
  return both;
}

MultisampleTarget::MultisampleTarget() {
  fetchProgram_ =
      buildProgram({shaders::sample_fetch_vert, shaders::sample_fetch_vert_file},
                   {shaders::sample_fetch_frag, shaders::sample_fetch_frag_file}, "sample fetch");
  sampleLocation_ = glGetUniformLocation(fetchProgram_, "uSample");
  glProgramUniform1i(fetchProgram_, glGetUniformLocation(fetchProgram_, "uDepth"), 0);
  glProgramUniform1i(fetchProgram_, glGetUniformLocation(fetchProgram_, "uIds"), 1);
  glCreateVertexArrays(1, &emptyVertexArray_);
  checkGl("sample fetch set-up");
}

MultisampleTarget::~MultisampleTarget() {
  release();
  glDeleteProgram(fetchProgram_);
  glDeleteVertexArrays(1, &emptyVertexArray_);
}

void MultisampleTarget::release() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteFramebuffers(1, &fetchFramebuffer_);
  const GLuint textures[3] = {depthTexture_, idTexture_, colourTexture_};
  glDeleteTextures(3, textures);
  const GLuint renderbuffers[2] = {fetchDepth_, fetchIds_};
  glDeleteRenderbuffers(2, renderbuffers);
  framebuffer_ = fetchFramebuffer_ = depthTexture_ = idTexture_ = colourTexture_ = fetchDepth_ =
      fetchIds_ = 0;
}

void MultisampleTarget::create(Viewport size, GLenum depthInternalFormat, int samples,
                               const char* depthFormatName, Attachments attachments) {
  release();
  size_ = size;
  samples_ = samples;
  const Viewport viewport = size;
  glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &depthTexture_);
  glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &idTexture_);
  // Fixed sample locations: the same positions in every pixel, so that one sheared matrix per
  // sample places the analytic side's rays on them (engine/MultisampleRun).
  glTextureStorage2DMultisample(depthTexture_, samples, depthInternalFormat, viewport.width,
                                viewport.height, GL_TRUE);
  glTextureStorage2DMultisample(idTexture_, samples, GL_R32UI, viewport.width, viewport.height,
                                GL_TRUE);
  glCreateFramebuffers(1, &framebuffer_);
  if (attachments == Attachments::AppColourAndIds) {
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &colourTexture_);
    glTextureStorage2DMultisample(colourTexture_, samples, GL_RGBA8, viewport.width,
                                  viewport.height, GL_TRUE);
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, colourTexture_, 0);
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, idTexture_, 0);
    const GLenum drawBuffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(framebuffer_, 2, drawBuffers);
  } else {
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, idTexture_, 0);
  }
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depthTexture_, 0);
  requireComplete(framebuffer_, "depth format " + std::string(depthFormatName) + " at " +
                                    std::to_string(samples) + " samples");

  glCreateRenderbuffers(1, &fetchDepth_);
  glCreateRenderbuffers(1, &fetchIds_);
  glNamedRenderbufferStorage(fetchDepth_, GL_R32F, viewport.width, viewport.height);
  glNamedRenderbufferStorage(fetchIds_, GL_R32UI, viewport.width, viewport.height);
  glCreateFramebuffers(1, &fetchFramebuffer_);
  glNamedFramebufferRenderbuffer(fetchFramebuffer_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                 fetchDepth_);
  glNamedFramebufferRenderbuffer(fetchFramebuffer_, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER,
                                 fetchIds_);
  const GLenum drawBuffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fetchFramebuffer_, 2, drawBuffers);
  requireComplete(fetchFramebuffer_, "the sample fetch targets (R32F, R32UI)");
  checkGl("multisample framebuffer set-up");
}

std::vector<glm::dvec2> MultisampleTarget::samplePositions() {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  std::vector<glm::dvec2> positions;
  for (int s = 0; s < samples_; ++s) {
    GLfloat position[2] = {0.5f, 0.5f};
    glGetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(s), position);
    positions.emplace_back(position[0], position[1]);
  }
  checkGl("sample positions");
  return positions;
}

std::vector<RasterFrame> MultisampleTarget::readSamples(glm::ivec4 region) {
  glBindFramebuffer(GL_FRAMEBUFFER, fetchFramebuffer_);
  glViewport(0, 0, size_.width, size_.height);
  // The fetch draws every pixel: nothing of the frame's state may cut or test it.
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_MULTISAMPLE);
  // What an app's render function may have left on (AppRender.hpp).
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_RASTERIZER_DISCARD);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glUseProgram(fetchProgram_);
  glBindTextureUnit(0, depthTexture_);
  glBindTextureUnit(1, idTexture_);
  glBindVertexArray(emptyVertexArray_);
  const Viewport read{region.z, region.w};
  const std::size_t count = static_cast<std::size_t>(read.width) * read.height;
  std::vector<RasterFrame> frames;
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glPixelStorei(GL_PACK_SKIP_ROWS, 0);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
  for (int s = 0; s < samples_; ++s) {
    glUniform1i(sampleLocation_, s);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    RasterFrame& frame = frames.emplace_back();
    frame.viewport = read;
    frame.depth.resize(count);
    frame.ids.resize(count);
    glNamedFramebufferReadBuffer(fetchFramebuffer_, GL_COLOR_ATTACHMENT0);
    glReadPixels(region.x, region.y, read.width, read.height, GL_RED, GL_FLOAT, frame.depth.data());
    glNamedFramebufferReadBuffer(fetchFramebuffer_, GL_COLOR_ATTACHMENT1);
    glReadPixels(region.x, region.y, read.width, read.height, GL_RED_INTEGER, GL_UNSIGNED_INT,
                 frame.ids.data());
  }
  glBindTextureUnit(0, 0);
  glBindTextureUnit(1, 0);
  checkGl("sample readback");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return frames;
}

}  // namespace clipray::gl

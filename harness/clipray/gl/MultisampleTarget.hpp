#pragma once
// Where a multisampled frame is drawn and how it is read back: a framebuffer with multisample depth
// and R32UI id textures (fixed sample locations), and a pass that copies sample s of every pixel
// into single-sample targets, one sample at a time, for glReadPixels (which cannot read a
// multisample buffer). Needs a current context with GL loaded (a Renderer's).

#include <glad/gl.h>

#include <vector>

#include <glm/glm.hpp>

#include "clipray/compare/Frames.hpp"

namespace clipray::gl {

class MultisampleTarget {
 public:
  MultisampleTarget();  // compiles the sample fetch program
  ~MultisampleTarget();
  MultisampleTarget(const MultisampleTarget&) = delete;
  MultisampleTarget& operator=(const MultisampleTarget&) = delete;

  // Fresh attachments of this size, depth format and sample count; GlError if incomplete.
  void create(Viewport viewport, GLenum depthInternalFormat, int samples,
              const char* depthFormatName);
  GLuint framebuffer() const { return framebuffer_; }
  // Where each sample lies in its pixel (glGetMultisamplefv(GL_SAMPLE_POSITION)): window
  // coordinates from the pixel's lower-left corner, in pixels, as the implementation reports
  // them for this framebuffer; never assumed.
  std::vector<glm::dvec2> samplePositions();
  // Sample s of every pixel as frame s: depth as the float the texture holds, ids as written.
  std::vector<RasterFrame> readSamples();

 private:
  void release();
  Viewport viewport_{};
  int samples_ = 0;
  GLuint framebuffer_ = 0, depthTexture_ = 0, idTexture_ = 0;
  // The single-sample targets the fetch pass writes: R32F depth, R32UI ids.
  GLuint fetchFramebuffer_ = 0, fetchDepth_ = 0, fetchIds_ = 0;
  GLuint fetchProgram_ = 0, emptyVertexArray_ = 0;
  GLint sampleLocation_ = -1;
};

// The sample counts above 1 that GL offers for multisample textures of both this depth format
// and R32UI (glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, ..., GL_SAMPLES)), ascending.
std::vector<int> multisampleCounts(GLenum depthInternalFormat);

}  // namespace clipray::gl

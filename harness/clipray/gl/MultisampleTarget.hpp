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

  // What the framebuffer holds besides depth: clipray's renderer writes ids to colour 0; an app's
  // render function gets the layout of its single-sample framebuffer (AppFrame): colour 0 RGBA8
  // for its colour, colour 1 the R32UI ids.
  enum class Attachments { Ids, AppColourAndIds };
  // Fresh attachments of this size, depth format and sample count; GlError if incomplete.
  void create(Viewport size, GLenum depthInternalFormat, int samples, const char* depthFormatName,
              Attachments attachments = Attachments::Ids);
  GLuint framebuffer() const { return framebuffer_; }
  // Where each sample lies in its pixel (glGetMultisamplefv(GL_SAMPLE_POSITION)): window
  // coordinates from the pixel's lower-left corner, in pixels, as the implementation reports
  // them for this framebuffer; never assumed.
  std::vector<glm::dvec2> samplePositions();
  // Sample s of every pixel of `region` (x, y, width, height from the lower-left corner) as frame
  // s: depth as the float the texture holds, ids as written.
  std::vector<RasterFrame> readSamples(glm::ivec4 region);
  std::vector<RasterFrame> readSamples() { return readSamples({0, 0, size_.width, size_.height}); }

 private:
  void release();
  Viewport size_{};
  int samples_ = 0;
  GLuint framebuffer_ = 0, depthTexture_ = 0, idTexture_ = 0, colourTexture_ = 0;
  // The single-sample targets the fetch pass writes: R32F depth, R32UI ids.
  GLuint fetchFramebuffer_ = 0, fetchDepth_ = 0, fetchIds_ = 0;
  GLuint fetchProgram_ = 0, emptyVertexArray_ = 0;
  GLint sampleLocation_ = -1;
};

// The sample counts above 1 that GL offers for multisample textures of both this depth format
// and R32UI (glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, ..., GL_SAMPLES)), ascending.
std::vector<int> multisampleCounts(GLenum depthInternalFormat);

}  // namespace clipray::gl

#pragma once
// The GL renderbuffer format of each depth format, for clipray's renderer and the app render
// function's framebuffer. Include after <glad/gl.h>.

#include "clipray/Conventions.hpp"

namespace clipray::gl {

// With stencil: the combined depth-stencil format (no 16-bit depth has one in GL).
inline GLenum depthInternalFormat(DepthFormat format, bool stencil = false) {
  switch (format) {
    case DepthFormat::Unorm16:
      return GL_DEPTH_COMPONENT16;
    case DepthFormat::Unorm24:
      return stencil ? GL_DEPTH24_STENCIL8 : GL_DEPTH_COMPONENT24;
    case DepthFormat::Float32:
      return stencil ? GL_DEPTH32F_STENCIL8 : GL_DEPTH_COMPONENT32F;
  }
  return GL_DEPTH_COMPONENT32F;
}

}  // namespace clipray::gl

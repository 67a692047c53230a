#pragma once
// The GL plumbing the renderer's passes share: GL error checks that name the stage, shaders
// compiled from embedded files whose errors name the file, programs linked with their log.

#include <glad/gl.h>

#include <string>
#include <vector>

namespace clipray::gl {

// GlError naming the first pending GL error and the stage it happened in.
void checkGl(const char* stage);

// A shader assembled from several files: the main file's #version line, the included files,
// then the rest of the main file. Each file is its own source string opened by `#line <l> <n>`
// (GLSL numbers source strings with n: 1 for the main file, 2... for the includes), so the info
// log's "n:line(column)" prefixes can be turned back into file names.
struct ShaderFile {
  const char* text;
  const char* name;
};
GLuint compileShaderFiles(GLenum kind, const std::vector<ShaderFile>& files);
// A shader from one file (compiled as its own source string too, so errors name it).
GLuint compileShader(GLenum kind, const char* source, const char* file);
// GlError with the link log where the program does not link.
GLuint linkProgram(GLuint vertex, GLuint fragment, const char* name);

// A program of one vertex and one fragment file, the shaders deleted once linked.
GLuint buildProgram(const ShaderFile& vertex, const ShaderFile& fragment, const char* name);

std::string glString(GLenum name);

}  // namespace clipray::gl

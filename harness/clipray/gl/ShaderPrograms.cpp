#include "clipray/gl/ShaderPrograms.hpp"

#include <algorithm>

#include "clipray/gl/Renderer.hpp"

namespace clipray::gl {

namespace {

const char* glErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default:
      return "unknown GL error";
  }
}

}  // namespace

void checkGl(const char* stage) {
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    throw GlError(std::string("GL: ") + glErrorName(error) + " during " + stage);
  }
}

GLuint compileShaderFiles(GLenum kind, const std::vector<ShaderFile>& files) {
  std::vector<std::string> parts;
  const std::string main = files.front().text;
  const std::size_t versionEnd = main.find('\n') + 1;
  parts.push_back(main.substr(0, versionEnd));
  for (std::size_t n = 1; n < files.size(); ++n) {
    parts.push_back("#line 1 " + std::to_string(n + 1) + "\n" + files[n].text);
  }
  // The main file's body starts on its line 2 (line 1 was #version).
  parts.push_back("#line 2 1\n" + main.substr(versionEnd));
  std::vector<const char*> sources;
  for (const std::string& part : parts) sources.push_back(part.c_str());
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, static_cast<GLsizei>(sources.size()), sources.data(), nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    std::vector<std::string> fileNames;
    for (const ShaderFile& file : files) fileNames.emplace_back(file.name);
    const std::string named = nameShaderSources(log.c_str(), fileNames);
    std::string names;
    for (const ShaderFile& file : files)
      names += (names.empty() ? "" : " + ") + std::string(file.name);
    throw GlError("GL: " + names + " does not compile:\n" + named);
  }
  return shader;
}

GLuint compileShader(GLenum kind, const char* source, const char* file) {
  return compileShaderFiles(kind, {{source, file}});
}

GLuint linkProgram(GLuint vertex, GLuint fragment, const char* name) {
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    glDeleteProgram(program);
    throw GlError(std::string("GL: program ") + name + " does not link:\n" + log.c_str());
  }
  return program;
}

GLuint buildProgram(const ShaderFile& vertex, const ShaderFile& fragment, const char* name) {
  const GLuint vertexShader = compileShader(GL_VERTEX_SHADER, vertex.text, vertex.name);
  const GLuint fragmentShader = compileShader(GL_FRAGMENT_SHADER, fragment.text, fragment.name);
  const GLuint program = linkProgram(vertexShader, fragmentShader, name);
  glDeleteShader(vertexShader);
  glDeleteShader(fragmentShader);
  return program;
}

std::string glString(GLenum name) {
  const GLubyte* text = glGetString(name);
  return text ? reinterpret_cast<const char*>(text) : "";
}

}  // namespace clipray::gl

#pragma once
// Internal to the demo: what its app state, panel and input handling share: the GL objects of the
// display pass, and the view matrices (column-major, p' = M * p, as everywhere in clipray).

#include <glad/gl.h>

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "PickDemo.hpp"

namespace clipray::demo {

struct PickDemo::Gpu {
  GLuint program = 0;
  GLuint vertexArray = 0;
  GLuint idTexture = 0;
  glm::ivec2 idTextureSize{0};
  GLuint colourBuffer = 0;
  GLuint colourTexture = 0;
  std::vector<unsigned char> lastFrame;  // RGBA of the last drawn frame, bottom row first
  glm::ivec2 lastFrameSize{0};
};

namespace detail {

inline glm::dmat4 translation(const glm::dvec3& t) {
  glm::dmat4 m(1.0);
  m[3] = glm::dvec4(t, 1.0);
  return m;
}

inline glm::dmat4 rotation(double radians, glm::dvec3 axis) {
  axis = glm::normalize(axis);
  const double c = std::cos(radians), s = std::sin(radians), k = 1.0 - c;
  const double x = axis.x, y = axis.y, z = axis.z;
  glm::dmat4 m(1.0);
  m[0] = {c + x * x * k, y * x * k + z * s, z * x * k - y * s, 0.0};
  m[1] = {x * y * k - z * s, c + y * y * k, z * y * k + x * s, 0.0};
  m[2] = {x * z * k + y * s, y * z * k - x * s, c + z * z * k, 0.0};
  return m;
}

}  // namespace detail

}  // namespace clipray::demo

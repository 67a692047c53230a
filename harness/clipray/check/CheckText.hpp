#pragma once
// How `clipray check` writes numbers in its messages and its text report: six significant digits,
// no "-0".

#include <cstdio>
#include <string>

#include <glm/glm.hpp>

#include "clipray/util/OptionValues.hpp"

namespace clipray::detail {

inline std::string checkNumber(double value) {
  return sixDigits(value);
}

inline std::string checkVector(const glm::dvec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", v.x + 0.0, v.y + 0.0, v.z + 0.0);
  return buffer;
}

}  // namespace clipray::detail

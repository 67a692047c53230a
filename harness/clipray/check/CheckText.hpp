#pragma once
// How `clipray check` writes numbers in its messages and its text report: six significant digits,
// no "-0".

#include <cmath>
#include <cstdio>
#include <string>

#include <glm/glm.hpp>

#include "clipray/check/MatrixReading.hpp"
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

// A reading with the digits its uncertainty allows, and the uncertainty where it shows at six
// digits: "0.150225 +-1.2e-06", "0.1".
inline std::string checkReading(const Uncertain& reading) {
  char error[32];
  std::snprintf(error, sizeof error, " +-%.2g", reading.error);
  return shownReading(reading) +
         (reading.error > 5e-7 * std::abs(reading.value) ? std::string(error) : "");
}

}  // namespace clipray::detail

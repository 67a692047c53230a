#pragma once
// Condition number of a matrix in the max-row-sum norm: the error of anything computed through its
// inverse (worldFromClip) is bounded by a small multiple of kappa * eps (relative). Computed in
// double: a bound needs a few digits only.

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace clipray::testing {

inline double conditionNumber(const glm::dmat4& m) {
  auto norm = [](const glm::dmat4& a) {
    double best = 0.0;
    for (int r = 0; r < 4; ++r) {
      best = std::max(
          best, std::abs(a[0][r]) + std::abs(a[1][r]) + std::abs(a[2][r]) + std::abs(a[3][r]));
    }
    return best;
  };
  return norm(m) * norm(glm::inverse(m));
}

}  // namespace clipray::testing

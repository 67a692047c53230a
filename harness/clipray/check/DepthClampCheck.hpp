#pragma once
// GL_DEPTH_CLAMP seen from picking: with it on, GL clips nothing at the near and far planes and
// gives fragments beyond them the depth range's nearer or farther end (OpenGL 4.6, 13.7 and
// 15.2.2), so the picture shows surfaces that a picking ray bounded by those planes cannot hit.

#include <optional>

#include "clipray/check/ConventionCheck.hpp"

namespace clipray {

// The note "depth-clamp-near-plane" when input.depthClampEnabledAt is set: where the clamped
// surfaces lie along the view (from the matrix's near and far planes under the declared
// convention), the window depth they are drawn at, and what that does to picks; nullopt when
// depth clamp is off.
std::optional<Finding> depthClampFinding(const CheckInput& input, const MatrixProperties& p);

}  // namespace clipray

// GL_DEPTH_CLAMP and picking rays (DepthClampCheck.hpp).

#include "clipray/check/DepthClampCheck.hpp"

#include <algorithm>

#include "clipray/check/CheckText.hpp"

namespace clipray {

std::optional<Finding> depthClampFinding(const CheckInput& input, const MatrixProperties& p) {
  if (!input.depthClampEnabledAt) return std::nullopt;
  const auto number = [](double value) { return detail::checkNumber(value); };
  // Near lands on the depth range's first value, far on its second (the other way round for a
  // reversed matrix, whose near plane is z_ndc = 1); GL clamps to the range's ends either way.
  const double nearWindowDepth = p.reversed ? input.depthRange.y : input.depthRange.x;
  const double farWindowDepth = p.reversed ? input.depthRange.x : input.depthRange.y;
  const std::string nearPlane =
      p.near ? "the near plane (" + shownReading(*p.near) + ")" : std::string("the near plane");
  const std::string inFront =
      p.perspective ? "between the eye and " + nearPlane
                    : "in front of " + nearPlane + ", however far (a parallel volume has no eye)";
  std::string message = "GL_DEPTH_CLAMP is on (" + *input.depthClampEnabledAt +
                        "): nothing is clipped at the near plane; a surface " + inFront +
                        " is drawn at window depth " + number(nearWindowDepth) +
                        ", the near plane's, so a picking ray that starts on the near plane "
                        "cannot hit it and unprojecting the depth buffer there gives a point on "
                        "the near plane, not on the surface";
  if (!p.infiniteFar) {
    message += "; likewise a surface beyond the far plane" +
               (p.far ? " (" + shownReading(*p.far) + ")" : std::string()) +
               " is drawn at window depth " + number(farWindowDepth) +
               ", past the end of a ray bounded by it";
  }
  return Finding{
      "info", "depth-clamp-near-plane", message,
      "while GL_DEPTH_CLAMP is on, start picking rays at the eye (t from 0" +
          std::string(p.perspective ? "" : ", or behind the near plane for a parallel volume") +
          ") and leave them unbounded beyond the far plane, and read a window depth of exactly " +
          number(std::min(nearWindowDepth, farWindowDepth)) + " or " +
          number(std::max(nearWindowDepth, farWindowDepth)) +
          " as clamped, not as a position; or disable it for the passes that are picked"};
}

}  // namespace clipray

#pragma once
// Which depth convention a matrix's near plane was built for, from its two readings (NO's and
// ZO's): a stated plane settles it; otherwise the reading that is a round number an app typed,
// against one that is not, at the uncertainty each reading carries.

#include <optional>
#include <string>

#include "clipray/check/MatrixReading.hpp"

namespace clipray::detail {

// A stated near or far plane agrees with a reading within the reading's uncertainty plus this
// (an app's own constant, typed again by hand).
inline constexpr double kStatedPlaneTolerance = 1e-4;

// Two readings of one plane, NO's and ZO's: which was built, and why. A stated plane settles it;
// otherwise the reading within its uncertainty of a round number (what an app types: 0.1, 0.05,
// 1000) is taken when the other is further than its uncertainty from every round number, and
// neither is taken when both or neither are.
struct BuildReading {
  std::string builtFor;
  std::string reason;
  std::optional<bool> statedMatches;
};

// behindCamera: readings are offsets from a camera position (orthographic), so a negative one puts
// the plane behind the camera, which an app rarely means when the other reading does not --
// except for a view volume centred on the camera (near = -far, with `far` the far plane's
// offset): gluOrtho2D and glOrtho(..., -1, 1) build exactly that, and its other reading (near 0)
// is just as natural, so it is left to the rules that follow.
BuildReading readBuild(const std::optional<Uncertain>& no, const std::optional<Uncertain>& zo,
                       std::optional<double> stated, const std::string& what,
                       bool behindCamera = false,
                       const std::optional<Uncertain>& far = std::nullopt);

}  // namespace clipray::detail

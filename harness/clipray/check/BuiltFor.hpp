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

BuildReading readBuild(const std::optional<Uncertain>& no, const std::optional<Uncertain>& zo,
                       std::optional<double> stated, const std::string& what);

// The same for an orthographic volume whose readings are offsets from the camera. There the NO
// and ZO readings of one matrix share the far plane f and satisfy zo = (no + f) / 2, and any sign
// is legal (glOrtho takes a negative near; OSG's HUD uses near -1, far 1.1). What an app sets in
// either convention is a round number (0 included: a volume starting at the camera) or a volume
// centred on the camera (near = -far: gluOrtho2D, glOrtho(..., -D, D) with any D). A reading is
// explained when it is one of those, and the matrix is decided only when exactly one reading is
// explained; so a ZO reading of exactly 0, which is the NO volume centred on the camera, decides
// nothing, and neither does the sign of a near plane.
BuildReading readOrthographicBuild(const Uncertain& no, const Uncertain& zo, const Uncertain& far,
                                   std::optional<double> stated);

}  // namespace clipray::detail

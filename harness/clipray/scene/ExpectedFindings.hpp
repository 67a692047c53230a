#pragma once
// The `clipray check` findings a scene camera may declare expected ("expectedFindings"): the codes
// of the check's errors and warnings that a reconcile run's check can give (its convention,
// reversed-Z, depth range, face culling and depth clamp; docs/check.md, Findings). Infos are never
// declared: they neither fail a run nor show on it. tests/unit/RunConventionCheckTest.cpp holds
// this list to docs/check.md's table, so a finding added there is added here.

#include <array>
#include <string_view>

namespace clipray {

inline constexpr std::array<std::string_view, 13> kDeclarableFindingCodes{
    "clear-depth-mismatch",
    "depth-convention-mismatch",
    "depth-range-reversed",
    "face-culling-keeps-insides",
    "far-plane-mismatch",
    "float-precision-risk",
    "infinite-far-plane",
    "likely-transposed",
    "near-plane-mismatch",
    "near-plane-precision",
    "reversed-z-mismatch",
    "reversed-z-without-zero-to-one",
    "y-flipped",
};

}  // namespace clipray

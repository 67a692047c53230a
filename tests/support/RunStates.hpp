#pragma once
// The GL states a GL-suite test sweeps: the three lower-left depth conventions, each also under an
// upper-left clip origin, and the three depth formats.

#include <vector>

#include "clipray/Conventions.hpp"

namespace clipray::testing {

inline const std::vector<DepthMode> kLowerLeftModes = {kNegativeOneToOne, kZeroToOne,
                                                       kZeroToOneReversed};
inline const std::vector<DepthFormat> kDepthFormats = {DepthFormat::Unorm16, DepthFormat::Unorm24,
                                                       DepthFormat::Float32};

// The same conventions drawn under glClipControl(GL_UPPER_LEFT, ...).
inline DepthMode upperLeft(DepthMode mode) {
  mode.origin = ClipOrigin::UpperLeft;
  return mode;
}

}  // namespace clipray::testing

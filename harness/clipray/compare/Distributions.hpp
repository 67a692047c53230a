#pragma once
// Internal to compare/: the max, median and 99th percentile of a reconcile's per-pixel figures.

#include <vector>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/util/FrameBuffers.hpp"

namespace clipray::detail {

// The quantiles of values (reordered in place): the value at rank round(fraction * (n - 1)).
Distribution distributionOf(std::vector<double>& values);

// distributionOf over the concatenation of parts, without concatenating them (see the .cpp).
Distribution distributionOfParts(const std::vector<const FrameVector<double>*>& parts);

}  // namespace clipray::detail

#pragma once
// Internal to compare/: the max, median and 99th percentile of a reconcile's per-pixel figures.

#include <vector>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/util/FrameBuffers.hpp"

namespace clipray::detail {

// The quantiles of values (reordered in place): the value at rank round(fraction * (n - 1)).
Distribution distributionOf(std::vector<double>& values);

using FigureParts = std::vector<const FrameVector<double>*>;

// distributionOf over the concatenation of parts, without concatenating them (see the .cpp).
Distribution distributionOfParts(const FigureParts& parts);
// The same by the bucket histogram alone (what distributionOfParts falls back to), for tests.
Distribution distributionOfPartsByHistogram(const FigureParts& parts);

}  // namespace clipray::detail

#pragma once
// Internal to compare/: the max, median and 99th percentile of a reconcile's per-pixel figures.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/util/FrameBuffers.hpp"

namespace clipray::detail {

// The quantiles of values (reordered in place): the value at rank round(fraction * (n - 1)).
Distribution distributionOf(std::vector<double>& values);

using FigureParts = std::vector<const FrameVector<double>*>;

// How a figure's values fall into the buckets of their bit patterns' top 16 bits (see the .cpp),
// with their count, largest bit pattern, and whether each is +0, positive or +inf.
struct FigureHistogram {
  std::vector<std::uint32_t> counts;
  std::uint64_t maxBits = 0;
  std::size_t count = 0;
  bool ordinary = true;
};
FigureHistogram histogramOf(const FigureParts& parts);
// The histogram of the union of the values the histograms were made of.
FigureHistogram sumOf(const std::vector<const FigureHistogram*>& histograms);

// distributionOf over the concatenation of parts, without concatenating them (see the .cpp);
// histogram is histogramOf(parts), or the sum of its parts' histograms.
Distribution distributionOfParts(const FigureParts& parts, const FigureHistogram& histogram);
Distribution distributionOfParts(const FigureParts& parts);

}  // namespace clipray::detail

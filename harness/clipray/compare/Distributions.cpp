// Quantiles of the per-pixel figures: by nth_element, or for the frame's parts by a histogram of
// the values' bit patterns that narrows each rank to one bucket first (the same values).

#include "clipray/compare/Distributions.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <utility>

namespace clipray::detail {

Distribution distributionOf(std::vector<double>& values) {
  Distribution result;
  if (values.empty()) return result;
  auto at = [&](double fraction) {
    const std::size_t index =
        std::min(values.size() - 1,
                 static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1) + 0.5));
    std::nth_element(values.begin(), values.begin() + index, values.end());
    return values[index];
  };
  result.p50 = at(0.5);
  result.p99 = at(0.99);
  result.max = *std::max_element(values.begin(), values.end());
  return result;
}

// The same Distribution as distributionOf over the concatenation of parts, without
// concatenating them and without sorting: for non-negative doubles (no NaN, no -0) the order of
// the values is the order of their bit patterns, so a histogram of the top 16 bits narrows each
// requested rank to one bucket, and only that bucket's values are looked at again. The values are
// the ones distributionOf picks (a rank's value does not depend on how ties or the order of the
// input fall). Anything else (NaN, where nth_element's answer depends on the input's order) takes
// distributionOf itself on the concatenation.

namespace {

constexpr int kBucketShift = 48;
constexpr std::uint64_t kPositiveInfinityBits = 0x7ff0000000000000ull;
constexpr std::size_t kBuckets = std::size_t{1} << (64 - kBucketShift);

// The values of one bucket: the first one met and how often it came, and every other value.
// A frame's flat surface gives one figure at every pixel, a bucket of a million copies of one
// value: counted, they are neither stored nor moved about.
struct BucketValues {
  std::uint64_t first = 0;
  std::size_t copies = 0;
  std::vector<std::uint64_t> others;

  void add(std::uint64_t bits) {
    if (copies == 0) {
      first = bits;
      copies = 1;
    } else if (bits == first) {
      ++copies;
    } else {
      others.push_back(bits);
    }
  }
  // The value of the given rank among the bucket's values: below the first value, its copies, or
  // above it (the others split at it, then nth_element on one side).
  double valueOfRank(std::size_t rank) {
    const auto above = std::partition(others.begin(), others.end(),
                                      [&](std::uint64_t bits) { return bits < first; });
    const auto below = static_cast<std::size_t>(above - others.begin());
    if (rank < below) {
      std::nth_element(others.begin(), others.begin() + static_cast<std::ptrdiff_t>(rank), above);
      return std::bit_cast<double>(others[rank]);
    }
    if (rank < below + copies) return std::bit_cast<double>(first);
    const auto past = static_cast<std::ptrdiff_t>(rank - below - copies);
    std::nth_element(above, above + past, others.end());
    return std::bit_cast<double>(above[past]);
  }
};

}  // namespace

FigureHistogram histogramOf(const FigureParts& parts) {
  FigureHistogram result;
  // Four interleaved histograms, summed after: neighbouring pixels' values mostly share a bucket,
  // and one histogram made each increment wait for the previous one's store.
  std::vector<std::uint32_t> histograms(4 * kBuckets, 0);
  std::uint64_t maxBits = 0;
  bool ordinary = true;  // every value is +0, positive or +inf
  for (const FrameVector<double>* part : parts) {
    // Four values at a time, one to each table (unrolled: the loop's own count would otherwise
    // pick the table), then the rest into the first.
    const double* values = part->data();
    const std::size_t size = part->size();
    result.count += size;
    const auto tally = [&](std::size_t table, double value) {
      const auto bits = std::bit_cast<std::uint64_t>(value);
      ordinary &= bits <= kPositiveInfinityBits;
      maxBits = std::max(maxBits, bits);
      ++histograms[table * kBuckets + (bits >> kBucketShift)];
    };
    std::size_t i = 0;
    for (; i + 4 <= size; i += 4) {
      for (std::size_t table = 0; table < 4; ++table) tally(table, values[i + table]);
    }
    for (; i < size; ++i) tally(0, values[i]);
  }
  result.counts.resize(kBuckets);
  for (std::size_t b = 0; b < kBuckets; ++b) {
    result.counts[b] = histograms[b] + histograms[kBuckets + b] + histograms[2 * kBuckets + b] +
                       histograms[3 * kBuckets + b];
  }
  result.maxBits = maxBits;
  result.ordinary = ordinary;
  return result;
}

FigureHistogram sumOf(const std::vector<const FigureHistogram*>& histograms) {
  FigureHistogram result;
  result.counts.assign(kBuckets, 0);
  for (const FigureHistogram* histogram : histograms) {
    for (std::size_t b = 0; b < kBuckets; ++b) result.counts[b] += histogram->counts[b];
    result.maxBits = std::max(result.maxBits, histogram->maxBits);
    result.count += histogram->count;
    result.ordinary &= histogram->ordinary;
  }
  return result;
}

Distribution distributionOfParts(const FigureParts& parts) {
  return distributionOfParts(parts, histogramOf(parts));
}

Distribution distributionOfParts(const FigureParts& parts, const FigureHistogram& histogram) {
  const std::size_t count = histogram.count;
  Distribution result;
  if (count == 0) return result;
  if (!histogram.ordinary || count > std::numeric_limits<std::uint32_t>::max()) {
    std::vector<double> all;
    all.reserve(count);
    for (const FrameVector<double>* part : parts) all.insert(all.end(), part->begin(), part->end());
    return distributionOf(all);
  }
  // The ranks distributionOf reads, each located in its bucket (the rank within the bucket).
  const auto locate = [&](double fraction) {
    std::size_t rank = std::min(
        count - 1, static_cast<std::size_t>(fraction * static_cast<double>(count - 1) + 0.5));
    std::size_t bucket = 0;
    while (rank >= histogram.counts[bucket]) rank -= histogram.counts[bucket++];
    return std::pair{bucket, rank};
  };
  const auto [bucket50, rank50] = locate(0.5);
  const auto [bucket99, rank99] = locate(0.99);
  // Both buckets' values in one pass over the parts.
  BucketValues in50, in99;
  for (const FrameVector<double>* part : parts) {
    for (const double value : *part) {
      const auto bits = std::bit_cast<std::uint64_t>(value);
      const std::uint64_t bucket = bits >> kBucketShift;
      if (bucket == bucket50) {
        in50.add(bits);
      } else if (bucket == bucket99) {
        in99.add(bits);
      }
    }
  }
  result.p50 = in50.valueOfRank(rank50);
  // Within one bucket, the second rank is found among the same values.
  result.p99 = (bucket99 == bucket50 ? in50 : in99).valueOfRank(rank99);
  result.max = std::bit_cast<double>(histogram.maxBits);
  return result;
}

}  // namespace clipray::detail

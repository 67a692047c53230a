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
// requested rank to one bucket, and nth_element runs on that bucket's few values only. The
// values are the ones distributionOf picks (a rank's value does not depend on how ties or the
// order of the input fall). Anything else (NaN, where nth_element's answer depends on the
// input's order) takes distributionOf itself on the concatenation.
Distribution distributionOfParts(const std::vector<const FrameVector<double>*>& parts) {
  std::size_t count = 0;
  for (const FrameVector<double>* part : parts) count += part->size();
  Distribution result;
  if (count == 0) return result;

  constexpr int kBucketShift = 48;
  constexpr std::uint64_t kPositiveInfinityBits = 0x7ff0000000000000ull;
  constexpr std::size_t kBuckets = std::size_t{1} << (64 - kBucketShift);
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
  std::vector<std::uint32_t> histogram(kBuckets);
  for (std::size_t b = 0; b < kBuckets; ++b) {
    histogram[b] = histograms[b] + histograms[kBuckets + b] + histograms[2 * kBuckets + b] +
                   histograms[3 * kBuckets + b];
  }
  if (!ordinary || count > std::numeric_limits<std::uint32_t>::max()) {
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
    while (rank >= histogram[bucket]) rank -= histogram[bucket++];
    return std::pair{bucket, rank};
  };
  const auto [bucket50, rank50] = locate(0.5);
  const auto [bucket99, rank99] = locate(0.99);
  // Both buckets' values in one pass over the parts.
  std::vector<std::uint64_t> in50, in99;
  in50.reserve(histogram[bucket50]);
  if (bucket99 != bucket50) in99.reserve(histogram[bucket99]);
  for (const FrameVector<double>* part : parts) {
    for (const double value : *part) {
      const auto bits = std::bit_cast<std::uint64_t>(value);
      const std::uint64_t bucket = bits >> kBucketShift;
      if (bucket == bucket50) {
        in50.push_back(bits);
      } else if (bucket == bucket99) {
        in99.push_back(bits);
      }
    }
  }
  const auto valueOfRank = [](std::vector<std::uint64_t>& inBucket, std::size_t rank) {
    // A frame's flat surface gives one figure at every pixel: a bucket of a million copies of one
    // value, where nth_element would still move them about. One pass finds that it is one value.
    const auto [lowest, highest] = std::minmax_element(inBucket.begin(), inBucket.end());
    if (*lowest == *highest) return std::bit_cast<double>(*lowest);
    std::nth_element(inBucket.begin(), inBucket.begin() + static_cast<std::ptrdiff_t>(rank),
                     inBucket.end());
    return std::bit_cast<double>(inBucket[rank]);
  };
  result.p50 = valueOfRank(in50, rank50);
  // Within one bucket, nth_element again on the partitioned values finds the same value.
  result.p99 = valueOfRank(bucket99 == bucket50 ? in50 : in99, rank99);
  result.max = std::bit_cast<double>(maxBits);
  return result;
}

}  // namespace clipray::detail

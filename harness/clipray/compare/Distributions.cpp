// Quantiles of the per-pixel figures: by nth_element; for a frame's parts, by one pass that counts
// the values around the ranks a sample points to, else by a histogram of the values' bit patterns
// that narrows each rank to one bucket first. The same values every way.

#include "clipray/compare/Distributions.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#define CLIPRAY_DISTRIBUTION_AVX2 1
#include <immintrin.h>
#else
#define CLIPRAY_DISTRIBUTION_AVX2 0
#endif

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>

#include "clipray/util/KernelChoice.hpp"

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

// The histogram way to the same Distribution as distributionOf over the concatenation of parts,
// without concatenating them and without sorting: for non-negative doubles (no NaN, no -0) the
// order of the values is the order of their bit patterns, so a histogram of the top 16 bits narrows
// each requested rank to one bucket, and only that bucket's values are looked at again. The values
// are the ones distributionOf picks (a rank's value does not depend on how ties or the order of the
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

// How the values fall into the buckets of their bit patterns' top 16 bits, with their count,
// largest bit pattern, and whether each is +0, positive or +inf.
struct FigureHistogram {
  std::vector<std::uint32_t> counts;
  std::uint64_t maxBits = 0;
  std::size_t count = 0;
  bool ordinary = true;
};

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

// The rank distributionOf reads for a fraction of count values.
std::size_t rankOf(double fraction, std::size_t count) {
  return std::min(count - 1,
                  static_cast<std::size_t>(fraction * static_cast<double>(count - 1) + 0.5));
}

// One rank's window [lo, hi] (two values of the sample): the values below lo counted, those equal
// to lo and to hi counted, those strictly between collected.
struct RankWindow {
  std::size_t rank = 0;
  double lo = 0.0, hi = 0.0;
  std::size_t below = 0, atLo = 0, atHi = 0;
  std::vector<double> inside;

  // The value of the rank, when the window holds it.
  std::optional<double> value() {
    if (rank < below) return std::nullopt;
    std::size_t r = rank - below;
    if (r < atLo) return lo;
    if (lo == hi) return std::nullopt;  // the copies of lo were counted twice; none lie between
    r -= atLo;
    if (r < inside.size()) {
      std::nth_element(inside.begin(), inside.begin() + static_cast<std::ptrdiff_t>(r),
                       inside.end());
      return inside[r];
    }
    r -= inside.size();
    if (r < atHi) return hi;
    return std::nullopt;
  }
};

// The counting pass over one part's values, four at a time where the CPU has AVX2 (a scalar
// loop otherwise, and for the last few). odd: a value that is not +0, positive or +inf (its
// sign bit set, or NaN); largest: the greatest value.
struct CountingPass {
  RankWindow* windows[2];
  bool odd = false;
  double largest = 0.0;

  void one(double v) {
    odd |= std::signbit(v) || std::isnan(v);
    largest = std::max(largest, v);
    for (RankWindow* w : windows) {
      if (v < w->lo) {
        ++w->below;
      } else {
        if (v == w->lo) ++w->atLo;
        if (v == w->hi) ++w->atHi;
        if (v > w->lo && v < w->hi) w->inside.push_back(v);
      }
    }
  }
  void scalar(const double* values, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) one(values[i]);
  }
#if CLIPRAY_DISTRIBUTION_AVX2
  // The four lanes' counts added (a member function, not a lambda: GCC 12 does not give a lambda
  // its enclosing function's target).
  __attribute__((target("avx2"))) static std::size_t laneSum(__m256i counts) {
    alignas(32) std::uint64_t lanes[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), counts);
    return static_cast<std::size_t>(lanes[0] + lanes[1] + lanes[2] + lanes[3]);
  }
  __attribute__((target("avx2"))) void wide(const double* values, std::size_t size) {
    __m256i below[2] = {}, atLo[2] = {}, atHi[2] = {};
    __m256d lo[2], hi[2];
    for (int k = 0; k < 2; ++k) {
      lo[k] = _mm256_set1_pd(windows[k]->lo);
      hi[k] = _mm256_set1_pd(windows[k]->hi);
    }
    __m256i signs = _mm256_setzero_si256();
    __m256d nan = _mm256_setzero_pd();
    __m256d top = _mm256_set1_pd(largest);
    std::size_t i = 0;
    for (; i + 4 <= size; i += 4) {
      const __m256d v = _mm256_loadu_pd(values + i);
      signs = _mm256_or_si256(signs, _mm256_castpd_si256(v));
      nan = _mm256_or_pd(nan, _mm256_cmp_pd(v, v, _CMP_UNORD_Q));
      top = _mm256_max_pd(top, v);
      for (int k = 0; k < 2; ++k) {
        // A lane's mask is -1 where it counts: subtracting it adds one.
        below[k] =
            _mm256_sub_epi64(below[k], _mm256_castpd_si256(_mm256_cmp_pd(v, lo[k], _CMP_LT_OQ)));
        atLo[k] =
            _mm256_sub_epi64(atLo[k], _mm256_castpd_si256(_mm256_cmp_pd(v, lo[k], _CMP_EQ_OQ)));
        atHi[k] =
            _mm256_sub_epi64(atHi[k], _mm256_castpd_si256(_mm256_cmp_pd(v, hi[k], _CMP_EQ_OQ)));
        const int between = _mm256_movemask_pd(_mm256_and_pd(_mm256_cmp_pd(v, lo[k], _CMP_GT_OQ),
                                                             _mm256_cmp_pd(v, hi[k], _CMP_LT_OQ)));
        if (between != 0) {
          for (int l = 0; l < 4; ++l) {
            if ((between >> l & 1) != 0) windows[k]->inside.push_back(values[i + l]);
          }
        }
      }
    }
    alignas(32) std::uint64_t lanes[4];
    alignas(32) double tops[4];
    for (int k = 0; k < 2; ++k) {
      windows[k]->below += laneSum(below[k]);
      windows[k]->atLo += laneSum(atLo[k]);
      windows[k]->atHi += laneSum(atHi[k]);
    }
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), signs);
    odd |= ((lanes[0] | lanes[1] | lanes[2] | lanes[3]) >> 63) != 0;
    odd |= _mm256_movemask_pd(nan) != 0;
    _mm256_store_pd(tops, top);
    for (const double t : tops) largest = std::max(largest, t);
    scalar(values + i, size - i);
  }
#endif
  void run(const double* values, std::size_t size) {
#if CLIPRAY_DISTRIBUTION_AVX2
    if (cpuHasAvx2() && simdKernelsChosen()) {
      wide(values, size);
      return;
    }
#endif
    scalar(values, size);
  }
  static bool cpuHasAvx2() {
#if CLIPRAY_DISTRIBUTION_AVX2
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2;
#else
    return false;
#endif
  }
};

// The sampled way: a strided sample of the values, sorted, gives for each rank two values that
// bracket it with a wide margin (the sample's rank +- 3 standard deviations of a binomial count,
// and 16 more); one pass counts the values below, at and between them; the rank's value is then
// found among the few between. When a bracket misses its rank (a sample the image's pattern
// fooled), or a value is NaN or negative, nothing is decided here (nullopt).
std::optional<Distribution> sampledDistribution(const FigureParts& parts, std::size_t count) {
  constexpr std::size_t kSample = 8192;
  std::vector<double> sample;
  sample.reserve(kSample);
  const std::size_t stride = count / kSample;
  std::size_t next = 0, offset = 0;
  for (const FrameVector<double>* part : parts) {
    for (; next < offset + part->size() && sample.size() < kSample; next += stride) {
      sample.push_back((*part)[next - offset]);
    }
    offset += part->size();
  }
  for (const double v : sample) {
    if (std::signbit(v) || std::isnan(v)) return std::nullopt;
  }
  std::sort(sample.begin(), sample.end());
  const double n = static_cast<double>(sample.size());
  RankWindow windows[2];
  const double fractions[2] = {0.5, 0.99};
  for (int k = 0; k < 2; ++k) {
    const double f = fractions[k];
    windows[k].rank = rankOf(f, count);
    const double position = static_cast<double>(windows[k].rank) / static_cast<double>(count) * n;
    const double margin = 3.0 * std::sqrt(n * f * (1.0 - f)) + 16.0;
    const auto at = [&](double p) {
      return sample[static_cast<std::size_t>(std::clamp(p, 0.0, n - 1.0))];
    };
    windows[k].lo = at(position - margin);
    windows[k].hi = at(position + margin);
  }
  CountingPass pass{{&windows[0], &windows[1]}};
  for (const FrameVector<double>* part : parts) pass.run(part->data(), part->size());
  if (pass.odd) return std::nullopt;
  const std::optional<double> p50 = windows[0].value();
  const std::optional<double> p99 = windows[1].value();
  if (!p50 || !p99) return std::nullopt;
  Distribution result;
  result.p50 = *p50;
  result.p99 = *p99;
  result.max = pass.largest;
  return result;
}

}  // namespace

Distribution distributionOfParts(const FigureParts& parts) {
  std::size_t count = 0;
  for (const FrameVector<double>* part : parts) count += part->size();
  // Below a few samples' worth the histogram costs about as little.
  if (count >= 16 * 8192) {
    if (const std::optional<Distribution> sampled = sampledDistribution(parts, count)) {
      return *sampled;
    }
  }
  return distributionOfPartsByHistogram(parts);
}

Distribution distributionOfPartsByHistogram(const FigureParts& parts) {
  const FigureHistogram histogram = histogramOf(parts);
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
    std::size_t rank = rankOf(fraction, count);
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

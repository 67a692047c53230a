// The report's quantiles of per-pixel figures: distributionOfParts (histograms of bit patterns
// over a frame's parts) must give distributionOf's values on the concatenation, bit for bit, on
// the kinds of data a frame gives: spread values, values crowded into one bucket and one
// sub-bucket, many ties, zeros and infinities, NaN (which takes distributionOf itself), parts of
// every size including empty ones.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "clipray/compare/Distributions.hpp"
#include "clipray/util/KernelChoice.hpp"

namespace clipray::detail {
namespace {

// Splits values into `partCount` parts of random sizes (some empty) and compares both answers.
void expectSameAsConcatenation(const std::vector<double>& values, int partCount,
                               std::mt19937_64& random) {
  std::vector<FrameVector<double>> parts(static_cast<std::size_t>(partCount));
  std::uniform_int_distribution<int> pick(0, partCount - 1);
  for (const double value : values) parts[static_cast<std::size_t>(pick(random))].push_back(value);
  if (partCount > 2) parts[1].clear();  // an empty part among them (its values are dropped)
  std::vector<const FrameVector<double>*> pointers;
  std::vector<double> concatenation;
  for (const FrameVector<double>& part : parts) {
    pointers.push_back(&part);
    concatenation.insert(concatenation.end(), part.begin(), part.end());
  }
  const Distribution expected = distributionOf(concatenation);
  // The sampled pass where there are enough values (its own fallback otherwise), its scalar loop
  // (the portable code), and the histogram alone.
  chooseKernels(KernelChoice::Portable);
  const Distribution portable = distributionOfParts(pointers);
  chooseKernels(KernelChoice::Simd);
  for (const Distribution& actual :
       {distributionOfParts(pointers), portable, distributionOfPartsByHistogram(pointers)}) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(actual.p50), std::bit_cast<std::uint64_t>(expected.p50))
        << actual.p50 << " vs " << expected.p50;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(actual.p99), std::bit_cast<std::uint64_t>(expected.p99))
        << actual.p99 << " vs " << expected.p99;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(actual.max), std::bit_cast<std::uint64_t>(expected.max))
        << actual.max << " vs " << expected.max;
  }
}

TEST(Distributions, PartsGiveTheQuantilesOfTheirConcatenation) {
  std::mt19937_64 random(20261126);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 48; ++trial) {
    // Up to 400,000 values: the sampled pass takes 131,072 and more.
    const std::size_t count = 1 + random() % 400000;
    std::vector<double> values(count);
    switch (trial % 6) {
      case 0:  // spread over many octaves
        for (double& v : values) v = std::exp2(60.0 * unit(random) - 40.0);
        break;
      case 1:  // crowded into one top-16-bit bucket (1 .. 1 + 1/16): the sub-bucket narrowing
        for (double& v : values) v = 1.0 + 0x1p-5 * unit(random);
        break;
      case 2:  // crowded into one sub-bucket too: the same top 32 bits, ties
        for (double& v : values) v = 0.25 + 0x1p-40 * std::floor(64.0 * unit(random));
        break;
      case 3:  // a flat floor: one value nearly everywhere, a few others
        for (double& v : values) v = unit(random) < 0.999 ? 0.40660191442293 : unit(random);
        break;
      case 5: {  // a flat floor in one bucket, met first after values above and below it
        for (double& v : values) {
          const double u = unit(random);
          v = u < 0.2 ? 0.375 - 0x1p-20 * unit(random)
                      : (u > 0.7 ? 0.375 + 0x1p-20 * unit(random) : 0.375);
        }
        values[0] = 0.375 + 0x1p-21;
        if (count > 1) values[1] = 0.375 - 0x1p-21;
        break;
      }
      case 4:  // zeros and infinities among them
        for (double& v : values) {
          const double u = unit(random);
          v = u < 0.3 ? 0.0 : u > 0.995 ? std::numeric_limits<double>::infinity() : u;
        }
        break;
    }
    expectSameAsConcatenation(values, 1 + trial % 7, random);
  }
}

TEST(Distributions, ASampleThePatternFoolsStillGivesTheExactRanks) {
  // Every 16th value is 1 and the others 2, 3, ...: a strided sample of 8,192 values (stride
  // count / 8,192 = 32) sees only ones, and the ranks lie far above its brackets.
  std::mt19937_64 random(3);
  std::vector<double> values(32 * 8192);
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = i % 16 == 0 ? 1.0 : 2.0 + static_cast<double>(i % 1000);
  }
  expectSameAsConcatenation(values, 1, random);
  expectSameAsConcatenation(values, 5, random);
}

TEST(Distributions, TheValueJustPastABracketIsNotTheBracketsEnd) {
  // 131,072 values; the sample takes every 16th, which hold 0, 1, ..., 8191. The median's rank,
  // 65,536, has a bracket of sample values [3944, 4247]; 61,288 other values of 0.5 make exactly
  // 65,536 values up to 4247, so the median is the next one, 4248, just past the bracket. The
  // rest, 8100, lie within the 99th percentile's bracket [8067, 8153], which holds that rank.
  std::mt19937_64 random(5);
  std::vector<double> values(131072);
  std::size_t small = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i % 16 == 0) {
      values[i] = static_cast<double>(i / 16);
    } else {
      values[i] = small++ < 61288 ? 0.5 : 8100.0;
    }
  }
  expectSameAsConcatenation(values, 1, random);
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted[65536], 4248.0);
  EXPECT_EQ(sorted[129761], 8100.0);
}

TEST(Distributions, NaNAmongThePartsTakesTheConcatenation) {
  std::mt19937_64 random(7);
  std::vector<double> values(5000);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 1.0 + 0x1p-30 * double(i % 97);
  values[1234] = std::numeric_limits<double>::quiet_NaN();
  expectSameAsConcatenation(values, 3, random);
}

TEST(Distributions, QuantilesAreTheValuesAtTheirRanks) {
  // 0, 1, ..., 1000 in reverse, in two parts: rank round(0.5 * 1000) = 500, round(0.99 * 1000) =
  // 990, and the largest.
  FrameVector<double> first, second;
  for (int v = 1000; v >= 0; --v) (v % 3 == 0 ? first : second).push_back(double(v));
  const Distribution d = distributionOfParts({&first, &second});
  EXPECT_EQ(d.p50, 500.0);
  EXPECT_EQ(d.p99, 990.0);
  EXPECT_EQ(d.max, 1000.0);
  // One bucket whose first value met sits in the middle: 200 values below it, 300 copies of it,
  // 501 above. Rank 500 is the first value above the copies, rank 990 the 491st.
  FrameVector<double> flat = {0.375};
  for (int k = 1; k <= 501; ++k) flat.push_back(0.375 + 0x1p-30 * k);
  for (int k = 1; k < 300; ++k) flat.push_back(0.375);
  for (int k = 1; k <= 200; ++k) flat.push_back(0.375 - 0x1p-30 * k);
  const Distribution floor = distributionOfParts({&flat});
  EXPECT_EQ(floor.p50, 0.375 + 0x1p-30);
  EXPECT_EQ(floor.p99, 0.375 + 0x1p-30 * 491);
  EXPECT_EQ(floor.max, 0.375 + 0x1p-30 * 501);
  const Distribution thirds = distributionOfParts({&first});
  EXPECT_EQ(thirds.max, 999.0);  // 999 = 3 * 333 is the largest multiple of 3
  EXPECT_EQ(distributionOfParts({}).max, 0.0);
}

}  // namespace
}  // namespace clipray::detail

// Frame buffers released by one run are handed to the next run of the same size (no fresh pages
// to zero); a size no kept block fits releases them all.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "clipray/util/FrameBuffers.hpp"

namespace clipray {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

TEST(FrameBuffers, ARunOfTheSameSizeGetsTheReleasedBlockBack) {
  void* first = allocateFrameBuffer(24 * kMiB);
  std::memset(first, 0x5a, 24 * kMiB);
  releaseFrameBuffer(first, 24 * kMiB);
  // 23 MiB rounds to 24 MiB of huge pages: the same block, contents as left (not zeroed).
  void* second = allocateFrameBuffer(23 * kMiB);
  EXPECT_EQ(second, first);
  EXPECT_EQ(static_cast<unsigned char*>(second)[12345], 0x5a);
  releaseFrameBuffer(second, 23 * kMiB);
  // The kept 24 MiB block is more than a quarter too big for 18 MiB (24 > 18 + 18 / 4): the miss
  // releases it and maps a fresh block, which is then the one kept.
  void* third = allocateFrameBuffer(18 * kMiB);
  releaseFrameBuffer(third, 18 * kMiB);
  void* fourth = allocateFrameBuffer(18 * kMiB);
  EXPECT_EQ(fourth, third);
  releaseFrameBuffer(fourth, 18 * kMiB);
}

TEST(FrameBuffers, SmallBuffersAreAlignedAndNotKept) {
  void* small = allocateFrameBuffer(1000);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small) % kFrameBufferAlignment, 0u);
  releaseFrameBuffer(small, 1000);
  FrameVector<double> values;
  values.resize(5);  // left unwritten by the allocator; written here
  for (double& v : values) v = 1.5;
  EXPECT_EQ(values[4], 1.5);
}

}  // namespace
}  // namespace clipray

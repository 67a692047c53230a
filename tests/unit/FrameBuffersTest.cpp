// Frame buffers released by one run are handed to the next run of the same size (no fresh pages
// to zero); a size no kept block fits gets a fresh block and leaves the kept ones be; what is kept
// stays below kMaxKeptFrameBufferBytes, the oldest freed first. (Sizes no other test uses: the
// kept blocks are the process's.)

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "clipray/util/FrameBuffers.hpp"

namespace clipray {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

TEST(FrameBuffers, ARunOfTheSameSizeGetsTheReleasedBlockBack) {
  void* first = allocateFrameBuffer(94 * kMiB);
  std::memset(first, 0x5a, 94 * kMiB);
  releaseFrameBuffer(first, 94 * kMiB);
  // 93 MiB rounds to 94 MiB of huge pages: the same block, contents as left (not zeroed).
  void* second = allocateFrameBuffer(93 * kMiB);
  EXPECT_EQ(second, first);
  EXPECT_EQ(static_cast<unsigned char*>(second)[12345], 0x5a);
  releaseFrameBuffer(second, 93 * kMiB);
  // The kept 94 MiB block is more than a quarter too big for 74 MiB (94 > 74 + 74 / 4): a fresh
  // block, and the 94 MiB one stays kept for a later run of its size.
  void* third = allocateFrameBuffer(74 * kMiB);
  EXPECT_NE(third, first);
  void* fourth = allocateFrameBuffer(94 * kMiB);
  EXPECT_EQ(fourth, first);
  releaseFrameBuffer(third, 74 * kMiB);
  EXPECT_EQ(allocateFrameBuffer(74 * kMiB), third);
  releaseFrameBuffer(third, 74 * kMiB);
  releaseFrameBuffer(fourth, 94 * kMiB);
}

TEST(FrameBuffers, AFrameOfBytesIsKeptToo) {
  // A 1080p per-pixel class image, one byte a pixel: just under one huge page, still kept.
  constexpr std::size_t kClassImageBytes = 1920 * 1080;
  static_assert(kClassImageBytes >= kMinKeptFrameBufferBytes);
  void* first = allocateFrameBuffer(kClassImageBytes);
  std::memset(first, 0x3c, kClassImageBytes);
  releaseFrameBuffer(first, kClassImageBytes);
  void* second = allocateFrameBuffer(kClassImageBytes);
  EXPECT_EQ(second, first);
  EXPECT_EQ(static_cast<unsigned char*>(second)[kClassImageBytes - 1], 0x3c);
  releaseFrameBuffer(second, kClassImageBytes);
}

TEST(FrameBuffers, WhatIsKeptStaysBelowTheLimitOldestFreedFirst) {
  // Three blocks of just over a third of the limit (address space only: never touched).
  const std::size_t bytes = kMaxKeptFrameBufferBytes / 3 + 2 * kMiB;
  void* blocks[3];
  for (void*& block : blocks) block = allocateFrameBuffer(bytes);
  for (void* block : blocks) releaseFrameBuffer(block, bytes);
  // Keeping the third would exceed the limit: the first released is freed, the others kept.
  void* again[2] = {allocateFrameBuffer(bytes), allocateFrameBuffer(bytes)};
  EXPECT_EQ(again[0], blocks[1]);
  EXPECT_EQ(again[1], blocks[2]);
  for (void* block : again) releaseFrameBuffer(block, bytes);
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

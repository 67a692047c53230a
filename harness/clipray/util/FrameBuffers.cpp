#include "clipray/util/FrameBuffers.hpp"

#include <cstdlib>
#include <mutex>

#include "clipray/util/HugePages.hpp"

namespace clipray {

namespace {
// Buffers from this size on are worth huge pages (and get their own mapping from malloc anyway).
constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

// Large frame buffers released by one run, kept for the next: a reconcile runs the same frame
// sizes camera after camera (rays, hits, per-pixel figures, bins), and a fresh mapping costs the
// kernel zeroing every page on first touch (about a quarter of a 1080p reconcile). A request that
// no kept block fits releases them all, so the process never holds much more than its largest
// run did, and kMaxCachedBytes bounds what is held between runs.
class ReleasedFrameBuffers {
 public:
  static constexpr std::size_t kMaxCachedBytes = std::size_t{1} << 30;

  // The smallest kept block of at least `rounded` bytes and at most a quarter more (a block is
  // recorded at the size it was last asked for, never more than it has), or nullptr -- and then
  // every kept block is freed.
  void* take(std::size_t rounded) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t best = blocks_.size();
    for (std::size_t k = 0; k < blocks_.size(); ++k) {
      const std::size_t bytes = blocks_[k].bytes;
      if (bytes >= rounded && bytes <= rounded + rounded / 4 &&
          (best == blocks_.size() || bytes < blocks_[best].bytes)) {
        best = k;
      }
    }
    if (best == blocks_.size()) {
      releaseAllLocked();
      return nullptr;
    }
    void* pointer = blocks_[best].pointer;
    cachedBytes_ -= blocks_[best].bytes;
    blocks_.erase(blocks_.begin() + static_cast<std::ptrdiff_t>(best));
    return pointer;
  }
  // Keeps the block when there is room, else frees it.
  void give(void* pointer, std::size_t rounded) noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    if (cachedBytes_ + rounded <= kMaxCachedBytes) {
      try {
        blocks_.push_back({pointer, rounded});
        cachedBytes_ += rounded;
        return;
      } catch (const std::bad_alloc&) {
      }
    }
    std::free(pointer);
  }

 private:
  struct Block {
    void* pointer;
    std::size_t bytes;
  };
  void releaseAllLocked() noexcept {
    for (const Block& block : blocks_) std::free(block.pointer);
    blocks_.clear();
    cachedBytes_ = 0;
  }
  std::mutex mutex_;
  std::vector<Block> blocks_;
  std::size_t cachedBytes_ = 0;
};

ReleasedFrameBuffers& releasedFrameBuffers() {
  // Never destroyed: a frame buffer released during static destruction still finds it (the
  // blocks stay reachable from here, and the process's exit returns them).
  static ReleasedFrameBuffers* released = new ReleasedFrameBuffers;
  return *released;
}

std::size_t hugePageRounded(std::size_t bytes) {
  return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
}
}  // namespace

void* allocateFrameBuffer(std::size_t bytes) {
  if (bytes < kHugePageBytes) {
    void* pointer = std::aligned_alloc(
        kFrameBufferAlignment,
        (bytes + kFrameBufferAlignment - 1) / kFrameBufferAlignment * kFrameBufferAlignment);
    if (pointer == nullptr && bytes != 0) throw std::bad_alloc();
    return pointer;
  }
  const std::size_t rounded = hugePageRounded(bytes);
  if (void* reused = releasedFrameBuffers().take(rounded)) return reused;
  void* pointer = std::aligned_alloc(kHugePageBytes, rounded);
  if (pointer == nullptr) throw std::bad_alloc();
  adviseHugePages(pointer, rounded);
  return pointer;
}

void releaseFrameBuffer(void* pointer, std::size_t bytes) noexcept {
  if (pointer == nullptr) return;
  if (bytes < kHugePageBytes) {
    std::free(pointer);
    return;
  }
  releasedFrameBuffers().give(pointer, hugePageRounded(bytes));
}

}  // namespace clipray

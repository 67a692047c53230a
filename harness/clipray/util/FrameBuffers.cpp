#include "clipray/util/FrameBuffers.hpp"

#include <cstdlib>
#include <mutex>

#include "clipray/util/HugePages.hpp"

namespace clipray {

namespace {
constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

// Large frame buffers released by one run, kept for the next: a reconcile runs the same frame
// sizes camera after camera (rays, hits, per-pixel figures, bins), and a fresh mapping costs the
// kernel zeroing every page on first touch (about a quarter of a 1080p reconcile; on a virtual
// machine whose host has reclaimed the memory, far more). A request that no kept block fits maps
// a fresh one and leaves the kept blocks be (a run asks for a dozen sizes in an order that varies:
// releasing them all on a miss made the next camera start from fresh pages again). What is kept
// stays below kMaxKeptFrameBufferBytes, the blocks released longest ago freed first.
class ReleasedFrameBuffers {
 public:
  // The smallest kept block of at least `rounded` bytes and at most a quarter more (a block is
  // recorded at the size it was last asked for, never more than it has), or nullptr.
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
    if (best == blocks_.size()) return nullptr;
    void* pointer = blocks_[best].pointer;
    cachedBytes_ -= blocks_[best].bytes;
    blocks_.erase(blocks_.begin() + static_cast<std::ptrdiff_t>(best));
    return pointer;
  }
  // Keeps the block (the oldest kept ones freed while the total is above the limit); a block
  // larger than the limit is freed at once.
  void give(void* pointer, std::size_t rounded) noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    if (rounded > kMaxKeptFrameBufferBytes) {
      std::free(pointer);
      return;
    }
    try {
      blocks_.push_back({pointer, rounded});
    } catch (const std::bad_alloc&) {
      std::free(pointer);
      return;
    }
    cachedBytes_ += rounded;
    std::size_t evicted = 0;
    while (cachedBytes_ > kMaxKeptFrameBufferBytes) {
      std::free(blocks_[evicted].pointer);
      cachedBytes_ -= blocks_[evicted].bytes;
      ++evicted;
    }
    blocks_.erase(blocks_.begin(), blocks_.begin() + static_cast<std::ptrdiff_t>(evicted));
  }

 private:
  struct Block {
    void* pointer;
    std::size_t bytes;
  };
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
  if (bytes < kMinKeptFrameBufferBytes) {
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
  if (bytes < kMinKeptFrameBufferBytes) {
    std::free(pointer);
    return;
  }
  releasedFrameBuffers().give(pointer, hugePageRounded(bytes));
}

}  // namespace clipray

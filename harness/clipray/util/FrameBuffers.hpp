#pragma once
// Storage for big per-frame arrays (rays, hits, per-pixel figures, screen-space bins): vectors
// whose allocator leaves elements unwritten and keeps released pages for the next frame of the
// same size, so a frame's arrays are written once, by the threads that fill them.

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace clipray {

// Allocator of the per-pixel frame buffers (a 1080p frame of rays is 116 MB). Two costs dominate
// filling such a buffer, not the work per pixel: std::vector value-initializes every element in
// the allocating thread before the worker threads overwrite it, and the first touch of each 4 KiB
// page faults. So resize() leaves elements uninitialized (the passes write every element; Ray and
// Hit are implicit-lifetime aggregates, so the storage already holds objects), large buffers ask
// the kernel for transparent huge pages (one fault per 2 MiB), and a released large buffer is kept
// for the next request it fits (the next camera of a reconcile): no fresh pages to zero at all.
inline constexpr std::size_t kFrameBufferAlignment = 64;
// Released large buffers kept for reuse stay below this many bytes in all.
inline constexpr std::size_t kMaxKeptFrameBufferBytes = std::size_t{512} << 20;
// Buffers from this size on are large: whole huge pages, kept when released. Half a huge page, so
// that a 1080p frame's per-pixel class image (2,073,600 bytes, just under 2 MiB) is kept too:
// malloc would give it back to the kernel on free, and every run would fault its pages in again.
inline constexpr std::size_t kMinKeptFrameBufferBytes = std::size_t{1} << 20;
void* allocateFrameBuffer(std::size_t bytes);  // throws std::bad_alloc
void releaseFrameBuffer(void* pointer, std::size_t bytes) noexcept;
template <class T>
struct FrameBufferAllocator {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
  using value_type = T;
  FrameBufferAllocator() = default;
  template <class U>
  FrameBufferAllocator(const FrameBufferAllocator<U>&) noexcept {}
  T* allocate(std::size_t count) {
    static_assert(alignof(T) <= kFrameBufferAlignment);
    if (count > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(allocateFrameBuffer(count * sizeof(T)));
  }
  void deallocate(T* pointer, std::size_t count) noexcept {
    releaseFrameBuffer(pointer, count * sizeof(T));
  }
  // resize(n) without a value: leave the element as allocated (written later by its pass).
  template <class U>
  void construct(U*) noexcept {}
  template <class U, class... Args>
  void construct(U* pointer, Args&&... args) {
    ::new (static_cast<void*>(pointer)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const FrameBufferAllocator<U>&) const noexcept {
    return true;
  }
};
// A per-pixel buffer: resize() does not initialize (see FrameBufferAllocator).
template <class T>
using FrameVector = std::vector<T, FrameBufferAllocator<T>>;

}  // namespace clipray

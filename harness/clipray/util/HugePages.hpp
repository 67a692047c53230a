#pragma once
// Transparent huge pages for big, freshly allocated arrays (frames, triangle copies, BVH build
// arrays): each is then faulted in one 2 MiB page at a time instead of 512 small ones when it is
// first written. Advice only: nothing changes where the kernel has none to give.

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace clipray {

// Asks for huge pages on the whole 2 MiB pages inside [data, data + bytes).
inline void adviseHugePages(const void* data, std::size_t bytes) {
#if defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t alignedBegin = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t alignedEnd = (begin + bytes) & ~(kHugePage - 1);
  if (alignedEnd > alignedBegin) {
    (void)madvise(reinterpret_cast<void*>(alignedBegin), alignedEnd - alignedBegin, MADV_HUGEPAGE);
  }
#else
  (void)data;
  (void)bytes;
#endif
}

// Reserves room for count elements, on huge pages where the kernel has them.
template <class T>
std::vector<T>& reserveOnHugePages(std::vector<T>& values, std::size_t count) {
  values.reserve(count);
  adviseHugePages(values.data(), values.capacity() * sizeof(T));
  return values;
}

}  // namespace clipray

#pragma once
// Invariants: what only a bug can break (clipray's own, or code calling it with what it promised
// not to), never what a user hands in (a scene, a matrix, an option value: those throw InputError
// and exit with status 2).
//
//   CLIPRAY_CHECK(frame.pixelCount() == count, "the raster and the analytic frame differ in size");
//
// CLIPRAY_CHECK is active in every build: keep its condition cheap (no loops over pixels, nothing
// in a hot path's inner loop). CLIPRAY_DCHECK is for the costly or hot ones: it checks only where
// NDEBUG is not defined (the release, asan and fuzz presets define it), and elsewhere compiles its
// arguments without evaluating them. The message is evaluated only when the check fails, so it may
// build a string. A failed check throws InternalError, which the tools report as "internal error,
// please report" with exit status 3 (util/ExitStatus.hpp). The line of a check written over
// several lines is its first under GCC, its last under clang.

#include <stdexcept>
#include <string>
#include <string_view>

namespace clipray {

// A broken invariant. what(): "harness/clipray/x/File.cpp:42: condition: message", the file
// relative to the source tree. A std::logic_error: like the standard library's, it reports a bug.
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

namespace detail {
// Throws InternalError("file:line: condition: message"; no ": message" when it is empty).
[[noreturn]] void checkFailed(const char* file, int line, const char* condition,
                              std::string_view message);
}  // namespace detail

}  // namespace clipray

#define CLIPRAY_CHECK(condition, message)                                        \
  do {                                                                           \
    if (!(condition)) [[unlikely]] {                                             \
      ::clipray::detail::checkFailed(__FILE__, __LINE__, #condition, (message)); \
    }                                                                            \
  } while (false)

#ifdef NDEBUG
#define CLIPRAY_DCHECK(condition, message) \
  do {                                     \
    if constexpr (false) {                 \
      static_cast<void>(!(condition));     \
      static_cast<void>(message);          \
    }                                      \
  } while (false)
#else
#define CLIPRAY_DCHECK(condition, message) CLIPRAY_CHECK(condition, message)
#endif

#pragma once
// Whether this build runs under AddressSanitizer (the asan preset): some tests skip what it cannot
// do (address-space limits), and the slowest sweeps check a part of their cases there (the
// release suite runs them whole). GCC defines __SANITIZE_ADDRESS__ under -fsanitize=address;
// clang 14 only answers __has_feature(address_sanitizer).

#if defined(__SANITIZE_ADDRESS__)
#define CLIPRAY_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CLIPRAY_UNDER_ASAN 1
#endif
#endif

namespace clipray::testing {

#if defined(CLIPRAY_UNDER_ASAN)
inline constexpr bool kUnderAddressSanitizer = true;
#else
inline constexpr bool kUnderAddressSanitizer = false;
#endif

}  // namespace clipray::testing

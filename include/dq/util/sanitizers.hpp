// Whether the code is built with AddressSanitizer or ThreadSanitizer (GCC defines __SANITIZE_*__,
// clang answers __has_feature). They reserve terabytes of address space, so the isolated importer
// sets no address-space limit on its worker there, and the tests that rely on one skip.
#pragma once

namespace dq {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitizedBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif
#else
inline constexpr bool kSanitizedBuild = false;
#endif

}  // namespace dq

// FRAMELESS_SLOW_BUILD is defined under AddressSanitizer or ThreadSanitizer (GCC or clang):
// tests that trace many rays scale their counts down there.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define FRAMELESS_SLOW_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define FRAMELESS_SLOW_BUILD 1
#endif
#endif

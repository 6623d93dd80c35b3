// Whether the test binary is built with a sanitizer (scripts/sanitize.sh: ASan + UBSan). The
// instrumented suite runs 2–20× slower; the few sweeps that only count inputs (a million random
// texels, every block of a crop) run a fifth of them there, which still executes every code path
// the sanitizers check, and the normal suite keeps the full count. Also: limits that sanitizers
// make impossible (RLIMIT_AS under ASan's shadow memory).
#pragma once

namespace ahd_test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

// `n` in the normal suite, n / 5 under a sanitizer (at least 1).
constexpr long sweep_count(long n) { return kSanitized ? (n / 5 > 0 ? n / 5 : 1) : n; }

}  // namespace ahd_test

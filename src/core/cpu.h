// The CPU's instruction-set extensions, detected once, and the one test override that turns them
// off. Every SIMD dispatch in the library asks here (the BC6H encoders, the half conversion,
// SHA-256), so the tests can force each path and compare its bytes with the plain path's.
#pragma once

namespace ahd::cpu {

// Extensions a dispatch may use. kSse2: the x86-64 baseline loops (compiled in, no run-time
// check; off = the plain scalar loops). kF16c: AVX + F16C with the OS saving the YMM state.
// kAvx2: AVX2 with the OS's YMM state. kAvx512: F, VL, BW, DQ with the OS's opmask and ZMM state.
// kShaNi: SHA + SSE4.1 + SSSE3.
enum Feature : unsigned {
  kSse2 = 1u << 0,
  kF16c = 1u << 1,
  kAvx2 = 1u << 2,
  kAvx512 = 1u << 3,
  kShaNi = 1u << 4,
};

// True when the CPU (and the build) has every extension of `features` and none of them is
// disabled by disable_for_tests. Cheap (one relaxed atomic load after the first call); safe from
// any thread.
bool has(unsigned features);

// Tests only: has() reports the extensions in `mask` as absent until the next call (0 = none
// disabled, the default). The library's only global switch; the bytes never depend on it (every
// path writes the same bytes), only the speed. Not for concurrent conversions.
void disable_for_tests(unsigned mask);

// Masks for the paths the tests force: the plain loops; SSE2 at most; AVX2 at most.
constexpr unsigned kAllSimd = kSse2 | kF16c | kAvx2 | kAvx512 | kShaNi;
constexpr unsigned kAboveSse2 = kF16c | kAvx2 | kAvx512 | kShaNi;
constexpr unsigned kAboveAvx2 = kAvx512;

}  // namespace ahd::cpu

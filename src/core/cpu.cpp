// CPUID and XGETBV read directly (clang 14's __builtin_cpu_supports does not know "f16c"), once.
#include "core/cpu.h"

#include <atomic>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#define AHD_CPU_X86 1
#endif

namespace ahd::cpu {

namespace {

std::atomic<unsigned> g_disabled{0};

#ifdef AHD_CPU_X86
unsigned xcr0() {
  unsigned lo = 0, hi = 0;
  __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
  return lo;
}
#endif

unsigned detect() {
  unsigned f = 0;
#ifdef __SSE2__
  f |= kSse2;
#endif
#ifdef AHD_CPU_X86
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return f;
  const unsigned c1 = c;
  const bool sse41_ssse3 = (c1 & bit_SSE4_1) && (c1 & bit_SSSE3);
  unsigned b7 = 0;
  if (__get_cpuid_max(0, nullptr) >= 7) {
    __cpuid_count(7, 0, a, b, c, d);
    b7 = b;
  }
  if (sse41_ssse3 && (b7 & (1u << 29))) f |= kShaNi;  // CPUID.(7,0):EBX.SHA
  const bool osxsave_avx = (c1 & (1u << 27)) && (c1 & (1u << 28));
  if (!osxsave_avx) return f;
  const unsigned x = xcr0();
  if ((x & 6u) != 6u) return f;  // XMM and YMM state enabled by the OS
  if (c1 & (1u << 29)) f |= kF16c;
  if (b7 & (1u << 5)) f |= kAvx2;
  const unsigned avx512 = (1u << 16) | (1u << 17) | (1u << 30) | (1u << 31);  // F, DQ, BW, VL
  // XMM, YMM, opmask and both ZMM states enabled by the OS.
  if ((f & kAvx2) && (x & 0xE6u) == 0xE6u && (b7 & avx512) == avx512) f |= kAvx512;
#endif
  return f;
}

}  // namespace

bool has(unsigned features) {
  static const unsigned detected = detect();
  const unsigned usable = detected & ~g_disabled.load(std::memory_order_relaxed);
  return (usable & features) == features;
}

void disable_for_tests(unsigned mask) { g_disabled.store(mask, std::memory_order_relaxed); }

}  // namespace ahd::cpu

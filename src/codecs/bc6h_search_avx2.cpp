// The searched encoder's index step with AVX2 (see bc6h_search_avx2.h). Every float operation is
// the SSE2 loop's (subtract, square, add the channels in the same order); only the minimum over
// the entries is taken eight lanes at a time, and a minimum does not depend on its order, so the
// indices and the error are the same. Built for plain x86-64: only this function is compiled for
// AVX2 (target attribute), and evaluate calls it only when the CPU reports AVX2.
#include "codecs/bc6h_search_avx2.h"

#include <atomic>

namespace ahd::bc6h {

namespace {
std::atomic<bool> g_force_sse2{false};
}

void force_search_sse2(bool sse2) { g_force_sse2.store(sse2, std::memory_order_relaxed); }
bool search_sse2_forced() { return g_force_sse2.load(std::memory_order_relaxed); }

}  // namespace ahd::bc6h

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

namespace ahd::bc6h {

__attribute__((target("avx2"))) double pick_indices_avx2(const float target[16][3], const float valid[16],
                                                          const float pal[2][3][16], uint16_t mask, int n, float off,
                                                          uint8_t idx[16]) {
  double total = 0;
  const int nv = n / 8;  // 1 (3-bit indices) or 2 (4-bit)
  for (int t = 0; t < 16; ++t) {
    const int r = (mask >> t) & 1;
    const __m256 l0 = _mm256_broadcast_ss(&target[t][0]), l1 = _mm256_broadcast_ss(&target[t][1]),
                 l2 = _mm256_broadcast_ss(&target[t][2]);
    __m256 ev[2];
    for (int v = 0; v < nv; ++v) {
      const __m256 d0 = _mm256_sub_ps(_mm256_load_ps(&pal[r][0][8 * v]), l0);
      const __m256 d1 = _mm256_sub_ps(_mm256_load_ps(&pal[r][1][8 * v]), l1);
      const __m256 d2 = _mm256_sub_ps(_mm256_load_ps(&pal[r][2][8 * v]), l2);
      ev[v] = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(d0, d0), _mm256_mul_ps(d1, d1)), _mm256_mul_ps(d2, d2));
    }
    __m256 mn = nv == 2 ? _mm256_min_ps(ev[0], ev[1]) : ev[0];
    mn = _mm256_min_ps(mn, _mm256_permute2f128_ps(mn, mn, 1));
    mn = _mm256_min_ps(mn, _mm256_shuffle_ps(mn, mn, _MM_SHUFFLE(1, 0, 3, 2)));
    mn = _mm256_min_ps(mn, _mm256_shuffle_ps(mn, mn, _MM_SHUFFLE(2, 3, 0, 1)));
    unsigned eq = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(ev[0], mn, _CMP_EQ_OQ)));
    if (nv == 2) eq |= unsigned(_mm256_movemask_ps(_mm256_cmp_ps(ev[1], mn, _CMP_EQ_OQ))) << 8;
    const float e = _mm256_cvtss_f32(mn);
    if (!(e < off)) return 1e300;
    idx[t] = uint8_t(__builtin_ctz(eq));
    total += valid[t] * e;
  }
  return total;
}

}  // namespace ahd::bc6h

#endif

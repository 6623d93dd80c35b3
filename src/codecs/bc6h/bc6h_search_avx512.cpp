// The searched encoder's index step with AVX-512: all sixteen texels in one vector, so each
// palette entry is compared once instead of once per half block (pick_indices_avx2's two
// vectors of eight). Every float operation is the AVX2 path's, lane for lane (subtract, square,
// add the channels in the same order, keep an entry only when strictly nearer), so the indices
// and the error are the same. Built for plain x86-64: only this function carries the AVX-512
// target attribute, and evaluate calls it only when cpu::has(cpu::kAvx512).
#include "codecs/bc6h/bc6h_search_avx512.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// GCC 12's AVX-512 intrinsics start their unmasked forms from _mm512_undefined_*(), which its
// -Wuninitialized reports once per inlined use (a known false positive of the header).
#pragma GCC diagnostic ignored "-Wuninitialized"
#ifndef __clang__  // clang has no such group (and warns on an unknown one)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

namespace ahd::bc6h {

__attribute__((target("avx512f,avx512vl,avx512bw,avx512dq"))) double pick_indices_avx512(
    const float target[3][16], const float valid[16], const float pal[2][3][16], uint16_t mask, int n, float off,
    uint8_t idx[16]) {
  const __m512 l0 = _mm512_loadu_ps(target[0]), l1 = _mm512_loadu_ps(target[1]), l2 = _mm512_loadu_ps(target[2]);
  __m512 mn = _mm512_set1_ps(__builtin_inff());
  __m512i mk = _mm512_setzero_si512();
  // Lane t takes region (mask >> t) & 1's entry: the mask is the blend's lane mask.
  const __mmask16 r1 = __mmask16(mask);
  for (int k = 0; k < n; ++k) {
    const __m512 p0 = _mm512_mask_blend_ps(r1, _mm512_set1_ps(pal[0][0][k]), _mm512_set1_ps(pal[1][0][k]));
    const __m512 p1 = _mm512_mask_blend_ps(r1, _mm512_set1_ps(pal[0][1][k]), _mm512_set1_ps(pal[1][1][k]));
    const __m512 p2 = _mm512_mask_blend_ps(r1, _mm512_set1_ps(pal[0][2][k]), _mm512_set1_ps(pal[1][2][k]));
    const __m512 d0 = _mm512_sub_ps(p0, l0), d1 = _mm512_sub_ps(p1, l1), d2 = _mm512_sub_ps(p2, l2);
    const __m512 e = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(d0, d0), _mm512_mul_ps(d1, d1)), _mm512_mul_ps(d2, d2));
    const __mmask16 nearer = _mm512_cmp_ps_mask(e, mn, _CMP_LT_OQ);
    mn = _mm512_mask_mov_ps(mn, nearer, e);
    mk = _mm512_mask_mov_epi32(mk, nearer, _mm512_set1_epi32(k));
  }
  alignas(64) float best[16];
  alignas(64) int best_k[16];
  _mm512_store_ps(best, mn);
  _mm512_store_si512(best_k, mk);
  double total = 0;
  for (int t = 0; t < 16; ++t) {
    if (!(best[t] < off)) return 1e300;
    idx[t] = uint8_t(best_k[t]);
    total += valid[t] * best[t];
  }
  return total;
}

}  // namespace ahd::bc6h

#endif

// hemisphere_sums with AVX-512: eight directions at a time, each lane running the plain path's
// operations in its order and the terms summed in the four-wide path's lanes and order
// (fit/hemisphere_sums.h), so the bits are the same. Only these functions carry the AVX-512
// target; hemisphere_sums calls them only when cpu::has(cpu::kAvx2 | cpu::kAvx512).
#include "fit/hemisphere_sums.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// GCC 12's AVX-512 intrinsics start their unmasked forms from _mm512_undefined_*(), which its
// -Wuninitialized reports once per inlined use (a known false positive of the header).
#pragma GCC diagnostic ignored "-Wuninitialized"
#ifndef __clang__  // clang has no such group (and warns on an unknown one)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "fit/hemisphere_sums_x86.h"

namespace ahd {

using namespace hemisphere_x86;

namespace {

#define AHD_AVX512 __attribute__((target("avx2,avx512f,avx512vl,avx512dq")))

// log2_lanes in eight lanes, the same operations lane by lane.
AHD_AVX512 inline __m512d log2_lanes8(__m512d x, bool* normal) {
  const __mmask8 ok = _mm512_cmp_pd_mask(x, _mm512_set1_pd(DBL_MIN), _CMP_GE_OQ) &
                      _mm512_cmp_pd_mask(x, _mm512_set1_pd(DBL_MAX), _CMP_LE_OQ);
  if (ok != 0xFF) *normal = false;
  const __m512i b = _mm512_castpd_si512(x);
  __m512i e = _mm512_srli_epi64(b, 52);
  const __m512i mb = _mm512_or_si512(_mm512_and_si512(b, _mm512_set1_epi64(0x000fffffffffffffll)),
                                     _mm512_set1_epi64(0x3ff0000000000000ll));
  __m512d m = _mm512_castsi512_pd(mb);
  const __mmask8 big = _mm512_cmp_pd_mask(m, _mm512_set1_pd(kSqrt2), _CMP_GT_OQ);
  m = _mm512_mask_mul_pd(m, big, m, _mm512_set1_pd(0.5));
  e = _mm512_mask_add_epi64(e, big, e, _mm512_set1_epi64(1));
  const __m512d two52 = _mm512_set1_pd(4503599627370496.0);
  const __m512d ed = _mm512_sub_pd(_mm512_castsi512_pd(_mm512_or_si512(e, _mm512_castpd_si512(two52))), two52);
  const __m512d k = _mm512_sub_pd(ed, _mm512_set1_pd(1023.0));
  const __m512d one = _mm512_set1_pd(1.0);
  const __m512d s = _mm512_div_pd(_mm512_sub_pd(m, one), _mm512_add_pd(m, one));
  const __m512d s2 = _mm512_mul_pd(s, s);
  __m512d p = _mm512_set1_pd(kLog2Series[9]);
  for (int i = 8; i >= 0; --i) p = _mm512_add_pd(_mm512_mul_pd(p, s2), _mm512_set1_pd(kLog2Series[i]));
  return _mm512_add_pd(k, _mm512_mul_pd(s, p));
}

AHD_AVX512 inline __m512d max0_8(__m512d v) { return _mm512_max_pd(v, _mm512_setzero_pd()); }

// Adds the eight lanes' terms to the four-lane sum as the four-wide path does: first directions
// k..k+3 (the low half), then k+4..k+7 (the high half).
AHD_AVX512 inline void add_halves(__m256d& sum, const __m512d t[3]) {
  for (int c = 0; c < 3; ++c) sum = _mm256_add_pd(sum, _mm512_castpd512_pd256(t[c]));
  for (int c = 0; c < 3; ++c) sum = _mm256_add_pd(sum, _mm512_extractf64x4_pd(t[c], 1));
}

}  // namespace

// Eight directions at a time: each lane computes the four-wide path's terms for its direction,
// and the terms go into the same four lanes in the same order (add_halves), so the sums are the
// four-wide path's bits; then a last group of four and the tail as there.
AHD_AVX512 HemisphereSums hemisphere_sums_avx512(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs,
                                                int n, bool with_log) {
  __m256d se = _mm256_setzero_pd(), sl = _mm256_setzero_pd(), lum = _mm256_setzero_pd();
  bool normal = true;
  const bool l2 = has_l2(p);
  const int full8 = n / 8 * 8;
  // Eight directions' x, y and z out of their 24 interleaved doubles a, b, c (three loads, two
  // permutes each: gathers were a tenth of the function's time): the components at 3i + k, those
  // below 16 from (a, b), the rest from c.
  const __m512i from_ab[3] = {_mm512_setr_epi64(0, 3, 6, 9, 12, 15, 0, 0), _mm512_setr_epi64(1, 4, 7, 10, 13, 0, 0, 0),
                              _mm512_setr_epi64(2, 5, 8, 11, 14, 0, 0, 0)};
  const __m512i from_c[3] = {_mm512_setr_epi64(0, 0, 0, 0, 0, 0, 2, 5), _mm512_setr_epi64(0, 0, 0, 0, 0, 0, 3, 6),
                             _mm512_setr_epi64(0, 0, 0, 0, 0, 1, 4, 7)};
  const __mmask8 lanes_c[3] = {0xC0, 0xE0, 0xE0};
  for (int k = 0; k < full8; k += 8) {
    const double* w = dirs + size_t(k) * 3;
    const __m512d a = _mm512_loadu_pd(w), b = _mm512_loadu_pd(w + 8), c = _mm512_loadu_pd(w + 16);
    __m512d wv[3];
    for (int i = 0; i < 3; ++i)
      wv[i] = _mm512_mask_permutexvar_pd(_mm512_permutex2var_pd(a, from_ab[i], b), lanes_c[i], from_c[i], c);
    const __m512d w0 = wv[0], w1 = wv[1], w2 = wv[2];
    const __m512d dot = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(w0, _mm512_set1_pd(l.d[0])),
                                                    _mm512_mul_pd(w1, _mm512_set1_pd(l.d[1]))),
                                      _mm512_mul_pd(w2, _mm512_set1_pd(l.d[2])));
    const __m512d cosine = max0_8(dot);
    __m512d tse[3], tsl[3] = {_mm512_setzero_pd(), _mm512_setzero_pd(), _mm512_setzero_pd()}, tlum[3];
    for (int c = 0; c < 3; ++c) {
      const IrradiancePoly& q = p[c];
      __m512d ref = _mm512_add_pd(_mm512_set1_pd(q.e0), _mm512_mul_pd(_mm512_set1_pd(q.e[0]), w0));
      ref = _mm512_add_pd(ref, _mm512_mul_pd(_mm512_set1_pd(q.e[1]), w1));
      ref = _mm512_add_pd(ref, _mm512_mul_pd(_mm512_set1_pd(q.e[2]), w2));
      if (l2)  // has_l2 (hemisphere_sums_x86.h): L1 texels' ±0 terms change no bit of the sums
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            ref = _mm512_add_pd(ref, _mm512_mul_pd(_mm512_mul_pd(wv[i], _mm512_set1_pd(q.q[i][j])), wv[j]));
      const __m512d got = _mm512_add_pd(_mm512_set1_pd(l.ca[c]), _mm512_mul_pd(cosine, _mm512_set1_pd(l.cd[c])));
      const __m512d d = _mm512_sub_pd(got, ref);
      tse[c] = _mm512_mul_pd(d, d);
      if (with_log) {
        const __m512d one = _mm512_set1_pd(1.0);
        const __m512d dl =
            log2_lanes8(_mm512_div_pd(_mm512_add_pd(one, max0_8(got)), _mm512_add_pd(one, max0_8(ref))), &normal);
        tsl[c] = _mm512_mul_pd(dl, dl);
      }
      tlum[c] = _mm512_mul_pd(_mm512_set1_pd(kLumaWeights[c]), ref);
    }
    add_halves(se, tse);
    if (with_log) add_halves(sl, tsl);
    add_halves(lum, tlum);
  }
  const int full4 = n / 4 * 4;
  if (full4 > full8) add_group4(p, l, dirs + size_t(full8) * 3, with_log, l2, se, sl, lum, &normal);
  return finish(p, l, dirs, full4, n, with_log, normal, se, sl, lum);
}

}  // namespace ahd

#else

namespace ahd {
HemisphereSums hemisphere_sums_avx512(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n,
                                      bool with_log) {
  return hemisphere_sums_plain(p, l, dirs, n, with_log);
}
}  // namespace ahd

#endif

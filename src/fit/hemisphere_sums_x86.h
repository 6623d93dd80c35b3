// The x86 paths' shared pieces of hemisphere_sums (fit/hemisphere_sums.h): the four-lane log2,
// one group of four directions, the tail. Internal to hemisphere_sums_avx2.cpp and
// hemisphere_sums_avx512.cpp; include only where __x86_64__ and GCC or clang.
#pragma once
#include <immintrin.h>

#include "fit/hemisphere_sums.h"

namespace ahd::hemisphere_x86 {

#define AHD_AVX2 __attribute__((target("avx2")))

// log2_series in four lanes; *normal &= whether every lane was a normal positive double (else the
// caller redoes the texel on the plain path, whose std::log2 handles the rest).
AHD_AVX2 inline __m256d log2_lanes(__m256d x, bool* normal) {
  const __m256d ok = _mm256_and_pd(_mm256_cmp_pd(x, _mm256_set1_pd(DBL_MIN), _CMP_GE_OQ),
                                   _mm256_cmp_pd(x, _mm256_set1_pd(DBL_MAX), _CMP_LE_OQ));
  if (_mm256_movemask_pd(ok) != 0xF) *normal = false;
  const __m256i b = _mm256_castpd_si256(x);
  __m256i e = _mm256_srli_epi64(b, 52);
  const __m256i mb = _mm256_or_si256(_mm256_and_si256(b, _mm256_set1_epi64x(0x000fffffffffffffll)),
                                     _mm256_set1_epi64x(0x3ff0000000000000ll));
  __m256d m = _mm256_castsi256_pd(mb);
  const __m256d big = _mm256_cmp_pd(m, _mm256_set1_pd(kSqrt2), _CMP_GT_OQ);
  m = _mm256_blendv_pd(m, _mm256_mul_pd(m, _mm256_set1_pd(0.5)), big);
  e = _mm256_sub_epi64(e, _mm256_castpd_si256(big));  // big lanes are all ones: −(−1) = +1
  // e < 2^52: or-ing it into 2^52's mantissa and subtracting 2^52 is its exact value.
  const __m256d two52 = _mm256_set1_pd(4503599627370496.0);
  const __m256d ed = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(e, _mm256_castpd_si256(two52))), two52);
  const __m256d k = _mm256_sub_pd(ed, _mm256_set1_pd(1023.0));
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d s = _mm256_div_pd(_mm256_sub_pd(m, one), _mm256_add_pd(m, one));
  const __m256d s2 = _mm256_mul_pd(s, s);
  __m256d p = _mm256_set1_pd(kLog2Series[9]);
  for (int i = 8; i >= 0; --i) p = _mm256_add_pd(_mm256_mul_pd(p, s2), _mm256_set1_pd(kLog2Series[i]));
  return _mm256_add_pd(k, _mm256_mul_pd(s, p));
}

// std::max(0.0, v): (0 < v) ? v : 0, NaN and −0 giving +0, as MAXPD(v, 0) does.
AHD_AVX2 inline __m256d max0(__m256d v) { return _mm256_max_pd(v, _mm256_setzero_pd()); }

// Without an L2 band (has_l2 of sh/sh.h), eval_irradiance's nine terms (w_i·q_ij)·w_j are each ±0,
// and adding ±0 leaves every sum's bits as they are: ref may come out −0 where the plain path has
// +0, but ref enters the sums only through max(0, ref) (+0 either way), got − ref (squared: +0
// either way) and luma·ref added to a lane that is +0 or nonzero (±0 added keeps it). So the wide
// paths skip them for L1 texels (test HemisphereSums.PathsGiveTheSameBits).

// One group of four directions w[0..11] added to the four lanes' sums, each lane running
// add_direction's operations in its order (both wide paths' step of four); l2 = has_l2(p).
AHD_AVX2 inline void add_group4(const IrradiancePoly p[3], const AhdLobe& l, const double* w, bool with_log,
                                bool l2, __m256d& se, __m256d& sl, __m256d& lum, bool* normal) {
  const __m256d w0 = _mm256_setr_pd(w[0], w[3], w[6], w[9]);
  const __m256d w1 = _mm256_setr_pd(w[1], w[4], w[7], w[10]);
  const __m256d w2 = _mm256_setr_pd(w[2], w[5], w[8], w[11]);
  const __m256d wv[3] = {w0, w1, w2};
  const __m256d dot = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(w0, _mm256_set1_pd(l.d[0])),
                                                  _mm256_mul_pd(w1, _mm256_set1_pd(l.d[1]))),
                                    _mm256_mul_pd(w2, _mm256_set1_pd(l.d[2])));
  const __m256d cosine = max0(dot);
  for (int c = 0; c < 3; ++c) {
    const IrradiancePoly& q = p[c];
    // eval_irradiance: ((e0 + e0·n0) + e1·n1) + e2·n2, then += (n_i·q_ij)·n_j in i, j order.
    __m256d ref = _mm256_add_pd(_mm256_set1_pd(q.e0), _mm256_mul_pd(_mm256_set1_pd(q.e[0]), w0));
    ref = _mm256_add_pd(ref, _mm256_mul_pd(_mm256_set1_pd(q.e[1]), w1));
    ref = _mm256_add_pd(ref, _mm256_mul_pd(_mm256_set1_pd(q.e[2]), w2));
    if (l2)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          ref = _mm256_add_pd(ref, _mm256_mul_pd(_mm256_mul_pd(wv[i], _mm256_set1_pd(q.q[i][j])), wv[j]));
    const __m256d got = _mm256_add_pd(_mm256_set1_pd(l.ca[c]), _mm256_mul_pd(cosine, _mm256_set1_pd(l.cd[c])));
    const __m256d d = _mm256_sub_pd(got, ref);
    se = _mm256_add_pd(se, _mm256_mul_pd(d, d));
    if (with_log) {
      const __m256d one = _mm256_set1_pd(1.0);
      const __m256d dl =
          log2_lanes(_mm256_div_pd(_mm256_add_pd(one, max0(got)), _mm256_add_pd(one, max0(ref))), normal);
      sl = _mm256_add_pd(sl, _mm256_mul_pd(dl, dl));
    }
    lum = _mm256_add_pd(lum, _mm256_mul_pd(_mm256_set1_pd(kLumaWeights[c]), ref));
  }
}

// The four lanes' sums and the directions from `from` on (add_direction), combined; the plain
// path's sums instead when a lane's ratio left the normal doubles (std::log2's cases there).
AHD_AVX2 inline HemisphereSums finish(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int from,
                                      int n, bool with_log, bool normal, __m256d se, __m256d sl, __m256d lum) {
  if (!normal) return hemisphere_sums_plain(p, l, dirs, n, with_log);
  alignas(32) double a[4], b[4], c[4];
  _mm256_store_pd(a, se);
  _mm256_store_pd(b, sl);
  _mm256_store_pd(c, lum);
  for (int k = from; k < n; ++k) add_direction(p, l, dirs + size_t(k) * 3, with_log, a[k & 3], b[k & 3], c[k & 3]);
  return combine_lanes(a, b, c);
}

}  // namespace ahd::hemisphere_x86

// The two-region candidate's AVX-512 steps (bc6h_fast_two_region.cpp calls them when
// cpu::has(cpu::kAvx512)): each lane's operations are the scalar step's in the same order, so the
// same bits. Only the functions here carry the AVX-512 target attribute.
#include "codecs/bc6h/bc6h_two_region.h"

#include "codecs/bc6h/bc6h_tables.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// GCC 12's AVX-512 intrinsics start their unmasked forms from _mm512_undefined_*(), which its
// -Wuninitialized reports once per inlined use (a known false positive of the header).
#pragma GCC diagnostic ignored "-Wuninitialized"
#ifndef __clang__  // clang has no such group (and warns on an unknown one)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

namespace ahd::bc6h::two_region {

// assign_region for both regions at once, the sixteen texels in one AVX-512 register: each
// texel's operations are assign_region's in the same order (one table of both regions' palettes
// per channel, entry 8r + k), and each region's error is the sum of its texels' in texel order,
// as assign_region adds them: err[r] is bit for bit assign_region's, idx the same indices.
__attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512dq"))) void assign_both_avx512(
    const Planes& f, uint16_t mask, const int e[4][3], int bits, uint8_t idx[16], float err[2]) {
  const __mmask16 r1 = __mmask16(mask);  // the texels of region 1
  __m512 tab[3], d[3], p0[3];
  for (int c = 0; c < 3; ++c) {
    alignas(64) float t[16];
    for (int r = 0; r < 2; ++r) {
      const int ua = unq(e[2 * r][c], bits), ub = unq(e[2 * r + 1][c], bits);
      for (int k = 0; k < 8; ++k) t[8 * r + k] = float(dec(interpolate(ua, ub, kWeights3[k])));
    }
    tab[c] = _mm512_load_ps(t);
    d[c] = _mm512_mask_blend_ps(r1, _mm512_set1_ps(t[7] - t[0]), _mm512_set1_ps(t[15] - t[8]));
    p0[c] = _mm512_mask_blend_ps(r1, _mm512_set1_ps(t[0]), _mm512_set1_ps(t[8]));
  }
  __m512 H[3], W[3], wd[3];
  for (int c = 0; c < 3; ++c) {
    H[c] = _mm512_loadu_ps(f.H[c]), W[c] = _mm512_loadu_ps(f.W[c]);
    wd[c] = _mm512_mul_ps(W[c], d[c]);
  }
  const __m512 num = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(wd[0], _mm512_sub_ps(H[0], p0[0])),
                                                 _mm512_mul_ps(wd[1], _mm512_sub_ps(H[1], p0[1]))),
                                   _mm512_mul_ps(wd[2], _mm512_sub_ps(H[2], p0[2])));
  const __m512 den = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(wd[0], d[0]), _mm512_mul_ps(wd[1], d[1])),
                                   _mm512_mul_ps(wd[2], d[2]));
  const __m512 zero = _mm512_setzero_ps(), k64 = _mm512_set1_ps(64.0f);
  const __m512 safe = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(den, zero, _CMP_GT_OQ), _mm512_set1_ps(1.0f), den);
  __m512 p = _mm512_div_ps(_mm512_mul_ps(k64, num), safe);
  // std::clamp(p, 0, 64): p < 0 → 0, 64 < p → 64.
  p = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(p, zero, _CMP_LT_OQ),
                           _mm512_mask_blend_ps(_mm512_cmp_ps_mask(k64, p, _CMP_LT_OQ), p, k64), zero);
  // kBelow.k[int(p)]: how many of the weights 9, 18, …, 64 are at or below int(p).
  const __m512i ip = _mm512_cvttps_epi32(p), one = _mm512_set1_epi32(1);
  __m512i k = _mm512_setzero_si512();
  for (int j = 1; j < 8; ++j) k = _mm512_mask_add_epi32(k, _mm512_cmpge_epi32_mask(ip, _mm512_set1_epi32(kW3[j])), k, one);
  const __m512i base = _mm512_mask_blend_epi32(r1, _mm512_setzero_si512(), _mm512_set1_epi32(8));
  const __mmask16 below7 = _mm512_cmplt_epi32_mask(k, _mm512_set1_epi32(7));
  const __m512i kn = _mm512_mask_add_epi32(k, below7, k, one);  // the next entry (k itself at 7)
  __m512 errs[2];
  for (int q = 0; q < 2; ++q) {
    const __m512i ti = _mm512_add_epi32(base, q ? kn : k);
    __m512 ec[3];
    for (int c = 0; c < 3; ++c) ec[c] = _mm512_sub_ps(_mm512_permutexvar_ps(ti, tab[c]), H[c]);
    errs[q] = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(W[0], ec[0]), ec[0]), _mm512_mul_ps(_mm512_mul_ps(W[1], ec[1]), ec[1])),
                            _mm512_mul_ps(_mm512_mul_ps(W[2], ec[2]), ec[2]));
  }
  const __m512 ek = errs[0], en = errs[1];
  const __mmask16 up = below7 & _mm512_cmp_ps_mask(en, ek, _CMP_LT_OQ);
  alignas(64) float best[16];
  _mm512_store_ps(best, _mm512_mask_blend_ps(up, ek, en));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(idx), _mm512_cvtepi32_epi8(_mm512_mask_blend_epi32(up, k, kn)));
  float total[2] = {0, 0};
  for (int t = 0; t < 16; ++t) total[(mask >> t) & 1] += best[t];
  err[0] = total[0], err[1] = total[1];
}

// axis_targets for both regions of kAvx512Partitions partitions at once, one (partition i, region r) per
// AVX-512 lane 2i + r: each lane's operations are axis_targets' in the same order (a texel
// outside the region or not valid leaves the lane's sums untouched, as its `continue` does; the
// early returns become selections), so targets[i][r] are bit for bit axis_targets'.
__attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512dq"))) void axis_targets_avx512(
    const Planes& f, const int parts[kAvx512Partitions], float targets[kAvx512Partitions][2][2][3]) {
  alignas(64) int in[16];  // lane 2i + r: the texels of region r of partition i (bit t)
  unsigned valid = 0;
  for (int t = 0; t < 16; ++t) valid |= unsigned(f.valid[t] != 0) << t;
  for (int i = 0; i < kAvx512Partitions; ++i) {
    const unsigned m = kPartitions[parts[i]];
    in[2 * i] = int(~m & valid & 0xFFFF), in[2 * i + 1] = int(m & valid);
  }
  const __m512i inv = _mm512_load_si512(in);
  __mmask16 mt[16];  // texel t's lanes
  for (int t = 0; t < 16; ++t) mt[t] = _mm512_test_epi32_mask(inv, _mm512_set1_epi32(1 << t));
  __m512 w = _mm512_setzero_ps(), mean[3], lo[3], hi[3];
  for (int c = 0; c < 3; ++c)
    mean[c] = _mm512_setzero_ps(), lo[c] = _mm512_set1_ps(1e30f), hi[c] = _mm512_set1_ps(-1e30f);
  for (int t = 0; t < 16; ++t) {
    const __mmask16 k = mt[t];
    w = _mm512_mask_add_ps(w, k, w, _mm512_set1_ps(f.tw[t]));
    for (int c = 0; c < 3; ++c) {
      const __m512 hv = _mm512_set1_ps(f.H[c][t]);
      mean[c] = _mm512_mask_add_ps(mean[c], k, mean[c], _mm512_set1_ps(f.tw[t] * f.H[c][t]));
      lo[c] = _mm512_mask_min_ps(lo[c], k, hv, lo[c]);  // std::min(lo, H): H < lo ? H : lo
      hi[c] = _mm512_mask_max_ps(hi[c], k, hv, hi[c]);  // std::max(hi, H): hi < H ? H : hi
    }
  }
  const __mmask16 empty = _mm512_cmp_ps_mask(lo[0], hi[0], _CMP_NLE_UQ);  // !(lo <= hi)
  const __mmask16 light = _mm512_cmp_ps_mask(w, _mm512_setzero_ps(), _CMP_NGT_UQ) & ~empty;  // !(w > 0)
  for (int c = 0; c < 3; ++c) mean[c] = _mm512_div_ps(mean[c], w);
  __m512 cov[6];
  for (int i = 0; i < 6; ++i) cov[i] = _mm512_setzero_ps();
  for (int t = 0; t < 16; ++t) {
    const __mmask16 k = mt[t];
    const __m512 tw = _mm512_set1_ps(f.tw[t]);
    const __m512 d0 = _mm512_sub_ps(_mm512_set1_ps(f.H[0][t]), mean[0]), d1 = _mm512_sub_ps(_mm512_set1_ps(f.H[1][t]), mean[1]),
                 d2 = _mm512_sub_ps(_mm512_set1_ps(f.H[2][t]), mean[2]);
    const __m512 w0 = _mm512_mul_ps(tw, d0), w1 = _mm512_mul_ps(tw, d1);
    cov[0] = _mm512_mask_add_ps(cov[0], k, cov[0], _mm512_mul_ps(w0, d0));
    cov[1] = _mm512_mask_add_ps(cov[1], k, cov[1], _mm512_mul_ps(w1, d1));
    cov[2] = _mm512_mask_add_ps(cov[2], k, cov[2], _mm512_mul_ps(_mm512_mul_ps(tw, d2), d2));
    cov[3] = _mm512_mask_add_ps(cov[3], k, cov[3], _mm512_mul_ps(w0, d1));
    cov[4] = _mm512_mask_add_ps(cov[4], k, cov[4], _mm512_mul_ps(w0, d2));
    cov[5] = _mm512_mask_add_ps(cov[5], k, cov[5], _mm512_mul_ps(w1, d2));
  }
  // principal_axis, lane-wise: a lane stops when its largest component is not above 0.
  __m512 ax[3] = {cov[0], cov[1], cov[2]};
  const __m512 sign = _mm512_set1_ps(-0.0f);
  __mmask16 going = 0xFFFF;
  for (int it = 0; it < 4; ++it) {
    const __m512 v0 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(cov[0], ax[0]), _mm512_mul_ps(cov[3], ax[1])), _mm512_mul_ps(cov[4], ax[2]));
    const __m512 v1 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(cov[3], ax[0]), _mm512_mul_ps(cov[1], ax[1])), _mm512_mul_ps(cov[5], ax[2]));
    const __m512 v2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(cov[4], ax[0]), _mm512_mul_ps(cov[5], ax[1])), _mm512_mul_ps(cov[2], ax[2]));
    const __m512 m = _mm512_max_ps(_mm512_max_ps(_mm512_andnot_ps(sign, v0), _mm512_andnot_ps(sign, v1)), _mm512_andnot_ps(sign, v2));
    going &= _mm512_cmp_ps_mask(m, _mm512_setzero_ps(), _CMP_GT_OQ);
    if (!going) break;
    ax[0] = _mm512_mask_div_ps(ax[0], going, v0, m);
    ax[1] = _mm512_mask_div_ps(ax[1], going, v1, m);
    ax[2] = _mm512_mask_div_ps(ax[2], going, v2, m);
  }
  __m512 len2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(ax[0], ax[0]), _mm512_mul_ps(ax[1], ax[1])), _mm512_mul_ps(ax[2], ax[2]));
  const __mmask16 flat = _mm512_cmp_ps_mask(len2, _mm512_setzero_ps(), _CMP_NGT_UQ);
  for (int c = 0; c < 3; ++c) ax[c] = _mm512_mask_blend_ps(flat, ax[c], _mm512_set1_ps(1.0f));
  len2 = _mm512_mask_blend_ps(flat, len2, _mm512_set1_ps(3.0f));
  __m512 tmin = _mm512_set1_ps(1e30f), tmax = _mm512_set1_ps(-1e30f);
  for (int t = 0; t < 16; ++t) {
    const __m512 p = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_sub_ps(_mm512_set1_ps(f.H[0][t]), mean[0]), ax[0]),
                                                 _mm512_mul_ps(_mm512_sub_ps(_mm512_set1_ps(f.H[1][t]), mean[1]), ax[1])),
                                   _mm512_mul_ps(_mm512_sub_ps(_mm512_set1_ps(f.H[2][t]), mean[2]), ax[2]));
    tmin = _mm512_mask_blend_ps(mt[t] & _mm512_cmp_ps_mask(p, tmin, _CMP_LT_OQ), tmin, p);
    tmax = _mm512_mask_blend_ps(mt[t] & _mm512_cmp_ps_mask(tmax, p, _CMP_LT_OQ), tmax, p);
  }
  const __m512 smin = _mm512_div_ps(tmin, len2), smax = _mm512_div_ps(tmax, len2);
  alignas(64) float out[2][3][16];
  for (int c = 0; c < 3; ++c) {
    const __m512 va = _mm512_add_ps(mean[c], _mm512_mul_ps(smin, ax[c]));
    const __m512 vb = _mm512_add_ps(mean[c], _mm512_mul_ps(smax, ax[c]));
    // std::clamp(v, lo, hi): v < lo → lo, hi < v → hi.
    __m512 a = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(va, lo[c], _CMP_LT_OQ),
                                    _mm512_mask_blend_ps(_mm512_cmp_ps_mask(hi[c], va, _CMP_LT_OQ), va, hi[c]), lo[c]);
    __m512 b = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(vb, lo[c], _CMP_LT_OQ),
                                    _mm512_mask_blend_ps(_mm512_cmp_ps_mask(hi[c], vb, _CMP_LT_OQ), vb, hi[c]), lo[c]);
    a = _mm512_mask_blend_ps(light, a, lo[c]), b = _mm512_mask_blend_ps(light, b, hi[c]);
    a = _mm512_mask_blend_ps(empty, a, _mm512_setzero_ps()), b = _mm512_mask_blend_ps(empty, b, _mm512_setzero_ps());
    _mm512_store_ps(out[0][c], a), _mm512_store_ps(out[1][c], b);
  }
  for (int i = 0; i < kAvx512Partitions; ++i)
    for (int r = 0; r < 2; ++r)
      for (int j = 0; j < 2; ++j)
        for (int c = 0; c < 3; ++c) targets[i][r][j][c] = out[j][c][2 * i + r];
}

}  // namespace ahd::bc6h::two_region

#else

namespace ahd::bc6h::two_region {
void assign_both_avx512(const Planes&, uint16_t, const int[4][3], int, uint8_t[16], float[2]) {}
void axis_targets_avx512(const Planes&, const int[kAvx512Partitions], float[kAvx512Partitions][2][2][3]) {}
}  // namespace ahd::bc6h::two_region

#endif

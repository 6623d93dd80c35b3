// The searched encoder's index step with AVX2 (see bc6h_search_avx2.h). Every float operation is
// the SSE2 loop's (subtract, square, add the channels in the same order); only the minimum over
// the entries is taken eight lanes at a time, and a minimum does not depend on its order, so the
// indices and the error are the same. Built for plain x86-64: only this function is compiled for
// AVX2 (target attribute), and evaluate calls it only when the CPU reports AVX2.
#include "codecs/bc6h/bc6h_search_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

namespace ahd::bc6h {

namespace {

// One vector of eight texels against every palette entry: the nearest entry's distance into mn
// and its index into mk. Region: 0 or 1 = every lane's (the entry broadcast as it is: the blend
// of the mixed case would pick the same lanes), 2 = per lane by rm.
template <int Region>
__attribute__((target("avx2"), always_inline)) inline void nearest_entries(const float pal[2][3][16], int n, __m256 rm,
                                                                            __m256 l0, __m256 l1, __m256 l2, __m256& mn,
                                                                            __m256i& mk) {
  mn = _mm256_set1_ps(__builtin_inff());
  mk = _mm256_setzero_si256();
  for (int k = 0; k < n; ++k) {
    __m256 p0, p1, p2;
    if constexpr (Region == 2) {
      p0 = _mm256_blendv_ps(_mm256_broadcast_ss(&pal[0][0][k]), _mm256_broadcast_ss(&pal[1][0][k]), rm);
      p1 = _mm256_blendv_ps(_mm256_broadcast_ss(&pal[0][1][k]), _mm256_broadcast_ss(&pal[1][1][k]), rm);
      p2 = _mm256_blendv_ps(_mm256_broadcast_ss(&pal[0][2][k]), _mm256_broadcast_ss(&pal[1][2][k]), rm);
    } else {
      p0 = _mm256_broadcast_ss(&pal[Region][0][k]), p1 = _mm256_broadcast_ss(&pal[Region][1][k]);
      p2 = _mm256_broadcast_ss(&pal[Region][2][k]);
    }
    const __m256 d0 = _mm256_sub_ps(p0, l0), d1 = _mm256_sub_ps(p1, l1), d2 = _mm256_sub_ps(p2, l2);
    const __m256 e = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(d0, d0), _mm256_mul_ps(d1, d1)), _mm256_mul_ps(d2, d2));
    const __m256 nearer = _mm256_cmp_ps(e, mn, _CMP_LT_OQ);
    mn = _mm256_blendv_ps(mn, e, nearer);
    mk = _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(mk), _mm256_castsi256_ps(_mm256_set1_epi32(k)), nearer));
  }
}

}  // namespace

// Eight texels per vector (texel lanes): each palette entry in turn is compared with eight
// texels' targets, the entry of each lane's region chosen by a blend (or broadcast when the eight
// texels share a region); a lane keeps an entry only when it is strictly nearer (so the first of
// equal entries stays, as in the loops over entries).
__attribute__((target("avx2"))) double pick_indices_avx2(const float target[3][16], const float valid[16],
                                                          const float pal[2][3][16], uint16_t mask, int n, float off,
                                                          uint8_t idx[16]) {
  alignas(32) float best[16];
  alignas(32) int best_k[16];
  const __m256i bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  for (int v = 0; v < 2; ++v) {
    const unsigned half = (mask >> (8 * v)) & 0xFF;
    const __m256 rm = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(half)), bits), bits));
    const __m256 l0 = _mm256_load_ps(&target[0][8 * v]), l1 = _mm256_load_ps(&target[1][8 * v]),
                 l2 = _mm256_load_ps(&target[2][8 * v]);
    __m256 mn;
    __m256i mk;
    if (half == 0) nearest_entries<0>(pal, n, rm, l0, l1, l2, mn, mk);
    else if (half == 0xFF) nearest_entries<1>(pal, n, rm, l0, l1, l2, mn, mk);
    else nearest_entries<2>(pal, n, rm, l0, l1, l2, mn, mk);
    _mm256_store_ps(&best[8 * v], mn);
    _mm256_store_si256(reinterpret_cast<__m256i*>(&best_k[8 * v]), mk);
  }
  double total = 0;
  for (int t = 0; t < 16; ++t) {
    if (!(best[t] < off)) return 1e300;
    idx[t] = uint8_t(best_k[t]);
    total += valid[t] * best[t];
  }
  return total;
}

namespace {

#define AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
using D = __m256d;
AVX2_INLINE D sel(D mask, D yes, D no) { return _mm256_or_pd(_mm256_and_pd(mask, yes), _mm256_andnot_pd(mask, no)); }
AVX2_INLINE D gt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
AVX2_INLINE D row(D p, D q, D r, D x, D y, D z) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(p, x), _mm256_mul_pd(q, y)), _mm256_mul_pd(r, z));
}
AVX2_INLINE D cov(const double* ss, D x, D y, D inv) { return _mm256_sub_pd(_mm256_loadu_pd(ss), _mm256_mul_pd(_mm256_mul_pd(x, y), inv)); }

}  // namespace

__attribute__((target("avx2"))) void pair_residuals_avx2(const double mm[][10][4], int pairs, double* out) {
  for (int j = 0; j < pairs; ++j) {
    const double (*m)[4] = mm[j];
    const D zero = _mm256_setzero_pd();
    const D w = _mm256_loadu_pd(m[0]), inv = _mm256_div_pd(_mm256_set1_pd(1.0), w);
    const D s0 = _mm256_loadu_pd(m[1]), s1 = _mm256_loadu_pd(m[2]), s2 = _mm256_loadu_pd(m[3]);
    const D xx = cov(m[4], s0, s0, inv), yy = cov(m[5], s1, s1, inv), zz = cov(m[6], s2, s2, inv),
            xy = cov(m[7], s0, s1, inv), xz = cov(m[8], s0, s2, inv), yz = cov(m[9], s1, s2, inv);
    const D trace = _mm256_add_pd(_mm256_add_pd(xx, yy), zz);
    const D c1 = _mm256_and_pd(gt(yy, xx), _mm256_cmp_pd(yy, zz, _CMP_GE_OQ));
    const D c2 = _mm256_andnot_pd(c1, _mm256_and_pd(gt(zz, xx), gt(zz, yy)));
    D v0 = sel(c1, xy, sel(c2, xz, xx)), v1 = sel(c1, yy, sel(c2, yz, xy)), v2 = sel(c1, yz, sel(c2, zz, xz));
    for (int it = 0; it < 2; ++it) {
      const D u0 = row(xx, xy, xz, v0, v1, v2), u1 = row(xy, yy, yz, v0, v1, v2), u2 = row(xz, yz, zz, v0, v1, v2);
      v0 = u0, v1 = u1, v2 = u2;
    }
    const D vv = row(v0, v1, v2, v0, v1, v2);
    const D cv0 = row(xx, xy, xz, v0, v1, v2), cv1 = row(xy, yy, yz, v0, v1, v2), cv2 = row(xz, yz, zz, v0, v1, v2);
    D r = _mm256_max_pd(_mm256_sub_pd(trace, _mm256_div_pd(row(v0, v1, v2, cv0, cv1, cv2), vv)), zero);
    r = sel(gt(vv, zero), r, trace);    // !(vv > 0): trace
    r = sel(gt(trace, zero), r, zero);  // !(trace > 0): 0
    r = sel(gt(w, zero), r, zero);      // w <= 0: 0
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, r);
    out[2 * j] = lanes[0] + lanes[1], out[2 * j + 1] = lanes[2] + lanes[3];
  }
}

__attribute__((target("avx2"))) void partition_moments_avx2(const double pt[16][12], const double all[10],
                                                               const uint16_t partitions[32], double m[16][10][4]) {
  // rows[g][s]: the moments of the subset s (bit i = texel 4g + i) of row g, three vectors of
  // components 0–3, 4–7 and 8–11 (10 and 11 are padding).
  alignas(32) double rows[4][16][12];
  for (int g = 0; g < 4; ++g) {
    for (int v = 0; v < 3; ++v) _mm256_store_pd(&rows[g][0][4 * v], _mm256_setzero_pd());
    for (int s = 1; s < 16; ++s) {
      const double* prev = rows[g][s & (s - 1)];
      const double* add = pt[4 * g + __builtin_ctz(unsigned(s))];
      for (int v = 0; v < 3; ++v)
        _mm256_store_pd(&rows[g][s][4 * v], _mm256_add_pd(_mm256_load_pd(&prev[4 * v]), _mm256_loadu_pd(&add[4 * v])));
    }
  }
  alignas(32) double allv[12] = {};
  for (int k = 0; k < 10; ++k) allv[k] = all[k];
  for (int p = 0; p < 32; ++p) {
    const unsigned mask = partitions[p];
    const double *m0 = rows[0][mask & 15], *m1 = rows[1][(mask >> 4) & 15], *m2 = rows[2][(mask >> 8) & 15],
                 *m3 = rows[3][mask >> 12];
    double(*mp)[4] = m[p / 2];
    const int lane = 2 * (p & 1);
    for (int v = 0; v < 3; ++v) {
      const D r1 = _mm256_add_pd(
          _mm256_add_pd(_mm256_add_pd(_mm256_load_pd(&m0[4 * v]), _mm256_load_pd(&m1[4 * v])), _mm256_load_pd(&m2[4 * v])),
          _mm256_load_pd(&m3[4 * v]));
      const D r0 = _mm256_sub_pd(_mm256_load_pd(&allv[4 * v]), r1);
      // (region 0, region 1) pairs of components 4v, 4v + 2 and 4v + 1, 4v + 3.
      const D lo = _mm256_unpacklo_pd(r0, r1), hi = _mm256_unpackhi_pd(r0, r1);
      _mm_storeu_pd(&mp[4 * v][lane], _mm256_castpd256_pd128(lo));
      _mm_storeu_pd(&mp[4 * v + 1][lane], _mm256_castpd256_pd128(hi));
      if (v < 2) {
        _mm_storeu_pd(&mp[4 * v + 2][lane], _mm256_extractf128_pd(lo, 1));
        _mm_storeu_pd(&mp[4 * v + 3][lane], _mm256_extractf128_pd(hi, 1));
      }
    }
  }
}

__attribute__((target("avx2"))) void region_moments_pair_avx2(const double q[16][3], const double tw[16],
                                                                 uint16_t mask, double mean[2][3], double cov[2][3][3]) {
  // Lanes (channel 0, 1, 2, weight): q is loaded with its fourth lane 0 and the weight lane set
  // to 1, so tw·(q, 1) = (tw·q, tw).
  const __m256i first3 = _mm256_setr_epi64x(-1, -1, -1, 0);
  const D one3 = _mm256_setr_pd(0, 0, 0, 1);
  D sum[2] = {_mm256_setzero_pd(), _mm256_setzero_pd()};
  D in[2][16];  // per texel: all ones in its region's lane set, zeros in the other's
  D qv[16];
  for (int k = 0; k < 16; ++k) {
    const bool r1 = (mask >> k) & 1;
    in[1][k] = _mm256_castsi256_pd(_mm256_set1_epi64x(r1 ? -1 : 0));
    in[0][k] = _mm256_castsi256_pd(_mm256_set1_epi64x(r1 ? 0 : -1));
    qv[k] = _mm256_maskload_pd(q[k], first3);
    const D v = _mm256_mul_pd(_mm256_set1_pd(tw[k]), _mm256_or_pd(qv[k], one3));
    sum[0] = _mm256_add_pd(sum[0], _mm256_and_pd(v, in[0][k]));
    sum[1] = _mm256_add_pd(sum[1], _mm256_and_pd(v, in[1][k]));
  }
  D mv[2];
  for (int r = 0; r < 2; ++r) {
    alignas(32) double s4[4];
    _mm256_store_pd(s4, sum[r]);
    const double sw = s4[3] <= 0 ? 1 : s4[3];
    for (int c = 0; c < 3; ++c) mean[r][c] = s4[c] / sw;
    mv[r] = _mm256_setr_pd(mean[r][0], mean[r][1], mean[r][2], 0);
  }
  D acc[2][3];
  for (auto& a : acc)
    for (D& x : a) x = _mm256_setzero_pd();
  for (int k = 0; k < 16; ++k) {
    const bool r1 = (mask >> k) & 1;
    const D d = _mm256_sub_pd(qv[k], r1 ? mv[1] : mv[0]);
    const D twd = _mm256_mul_pd(_mm256_set1_pd(tw[k]), d);  // (tw·d[i]) in lane i
    const D x0 = _mm256_mul_pd(_mm256_permute4x64_pd(twd, 0x00), d);
    const D x1 = _mm256_mul_pd(_mm256_permute4x64_pd(twd, 0x55), d);
    const D x2 = _mm256_mul_pd(_mm256_permute4x64_pd(twd, 0xAA), d);
    for (int r = 0; r < 2; ++r) {
      acc[r][0] = _mm256_add_pd(acc[r][0], _mm256_and_pd(x0, in[r][k]));
      acc[r][1] = _mm256_add_pd(acc[r][1], _mm256_and_pd(x1, in[r][k]));
      acc[r][2] = _mm256_add_pd(acc[r][2], _mm256_and_pd(x2, in[r][k]));
    }
  }
  for (int r = 0; r < 2; ++r)
    for (int i = 0; i < 3; ++i) {
      alignas(32) double row[4];
      _mm256_store_pd(row, acc[r][i]);
      for (int j = 0; j < 3; ++j) cov[r][i][j] = row[j];
    }
}

namespace {

// held_channel_error_avx2's body (the pair version runs two of them side by side).
__attribute__((target("avx2"), always_inline)) inline float channel_error(const int u[4], int ng, const float fr[16],
                                                                           const float fwa[16], const float fwb[16],
                                                                           const float gn[16], const float gm[16],
                                                                           int cap, const float* L, bool* over) {
  const __m256 a0 = _mm256_set1_ps(float(u[0])), b0 = _mm256_set1_ps(float(u[1]));
  const __m256 da = _mm256_set1_ps(float(u[2] - u[0])), db = _mm256_set1_ps(float(u[3] - u[1]));
  const __m256 inv64 = _mm256_set1_ps(1.0f / 64.0f), k31 = _mm256_set1_ps(31.0f), k32 = _mm256_set1_ps(32.0f);
  const __m256i capv = _mm256_set1_epi32(cap);
  __m256i out = _mm256_setzero_si256();
  __m128 acc = _mm_setzero_ps();
  for (int i = 0; i < ng; i += 8) {
    const __m256 r = _mm256_load_ps(&fr[i]);
    const __m256 a = _mm256_add_ps(a0, _mm256_mul_ps(r, da)), bb = _mm256_add_ps(b0, _mm256_mul_ps(r, db));
    const __m256 sum =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(a, _mm256_load_ps(&fwa[i])), _mm256_mul_ps(bb, _mm256_load_ps(&fwb[i]))), k32);
    const __m256 ci = _mm256_cvtepi32_ps(_mm256_cvttps_epi32(_mm256_mul_ps(sum, inv64)));
    const __m256i h = _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_mul_ps(ci, k31), inv64));
    out = _mm256_or_si256(out, _mm256_cmpgt_epi32(h, capv));
    // Eight loads rather than a gather: the same values, and the gather is microcoded on the
    // project's AMD machine (this function took 13 % of hard's time with it, 6 % of the
    // instructions).
    alignas(32) int hv[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(hv), h);
    const __m256 lv = _mm256_setr_ps(L[hv[0]], L[hv[1]], L[hv[2]], L[hv[3]], L[hv[4]], L[hv[5]], L[hv[6]], L[hv[7]]);
    const __m256 d = _mm256_sub_ps(lv, _mm256_load_ps(&gm[i]));
    const __m256 x = _mm256_mul_ps(_mm256_mul_ps(_mm256_load_ps(&gn[i]), d), d);
    // The SSE2 loop's accumulator: groups i..i+3, then i+4..i+7 (when it reaches them).
    acc = _mm_add_ps(acc, _mm256_castps256_ps128(x));
    if (i + 4 < ng) acc = _mm_add_ps(acc, _mm256_extractf128_ps(x, 1));
  }
  alignas(16) float part[4];
  _mm_store_ps(part, acc);
  *over = _mm256_movemask_epi8(out) != 0;
  return (part[0] + part[1]) + (part[2] + part[3]);
}

}  // namespace

__attribute__((target("avx2"))) float held_channel_error_avx2(const int u[4], int ng, const float fr[16],
                                                                const float fwa[16], const float fwb[16],
                                                                const float gn[16], const float gm[16], int cap,
                                                                const float* L, bool* over) {
  return channel_error(u, ng, fr, fwa, fwb, gn, gm, cap, L, over);
}

__attribute__((target("avx2"))) void held_channel_error_pair_avx2(const int ua[4], const int ub[4], int ng,
                                                                    const float fr[16], const float fwa[16],
                                                                    const float fwb[16], const float gn[16],
                                                                    const float gm[16], int cap, const float* L,
                                                                    float err[2], bool over[2]) {
  err[0] = channel_error(ua, ng, fr, fwa, fwb, gn, gm, cap, L, &over[0]);
  err[1] = channel_error(ub, ng, fr, fwa, fwb, gn, gm, cap, L, &over[1]);
}

}  // namespace ahd::bc6h

#endif

// BC6H `fast`, eight blocks at a time: the fit of fit_one_region_fast (bc6h_fast.cpp) with one
// block per AVX2 lane, so that the per-block scalar work (the principal axis, the endpoint
// quantisation with its mode choice and cap, the least-squares solve) and the palette lookups of
// the index step (per-texel gathers in the one-block code) become lane-wise arithmetic.
//
// Same bytes as the one-block path, lane by lane: every float operation is the one-block code's,
// in the same order (no FMA: this file enables AVX2 only, and the build has -ffp-contract=off);
// a lane's branches become masks, and a loop runs while any lane still needs it, changing only
// the lanes that do. No lane reads another lane, so a block's bytes never depend on the other
// blocks of its batch (tested: blocks alone, in mixed batches, and with the scalar path forced).
//
// Built for plain x86-64: only the functions here are compiled for AVX2 (target attribute, no
// per-file flags, so no inline function of a shared header is ever compiled with AVX2), and
// bc6h_fast.cpp calls them only when the CPU reports AVX2 (cpu_has_avx2).
#include "codecs/bc6h_fast.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#include <immintrin.h>

#include <cstring>

namespace ahd::bc6h {

namespace {

#define AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
#define AVX2_FN __attribute__((target("avx2")))

using F = __m256;
using I = __m256i;

// The one-region modes by precision (as bc6h_fast.cpp's kModes): endpoint bits and delta bits.
constexpr int kEpb[4] = {16, 12, 11, 10};
constexpr int kDelta[4] = {4, 8, 9, 10};
constexpr int kModeNumber[4] = {13, 12, 11, 10};

AVX2_INLINE F f32(float v) { return _mm256_set1_ps(v); }
AVX2_INLINE I i32(int v) { return _mm256_set1_epi32(v); }
AVX2_INLINE F fabs8(F v) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), v); }
AVX2_INLINE F select(F mask, F yes, F no) { return _mm256_blendv_ps(no, yes, mask); }
AVX2_INLINE I select(I mask, I yes, I no) { return _mm256_blendv_epi8(no, yes, mask); }
AVX2_INLINE F as_f(I v) { return _mm256_castsi256_ps(v); }
AVX2_INLINE I as_i(F v) { return _mm256_castps_si256(v); }
AVX2_INLINE bool any(F m) { return _mm256_movemask_ps(m) != 0; }
AVX2_INLINE bool any(I m) { return _mm256_movemask_ps(as_f(m)) != 0; }
// The one-block code's std::min / std::max of non-NaN floats (equal values are equal either way).
AVX2_INLINE F lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }

// unquantize_u for each lane's endpoint bits (lanes may be in different modes).
AVX2_INLINE I unquantize(I e, I bits) {
  const I maxv = _mm256_sub_epi32(_mm256_sllv_epi32(i32(1), bits), i32(1));
  const I mid = _mm256_srlv_epi32(_mm256_add_epi32(_mm256_slli_epi32(e, 16), i32(0x8000)), bits);
  I r = select(_mm256_cmpeq_epi32(e, maxv), i32(0xFFFF), mid);
  r = _mm256_andnot_si256(_mm256_cmpeq_epi32(e, _mm256_setzero_si256()), r);
  return select(_mm256_cmpgt_epi32(bits, i32(14)), e, r);
}
// The decoder's 16-bit value → half bits: (c·31) >> 6.
AVX2_INLINE I decode_h(I c) { return _mm256_srli_epi32(_mm256_sub_epi32(_mm256_slli_epi32(c, 5), c), 6); }

// unquantize_u + decode_h for `bits` the same in every lane (immediate shifts).
template <int bits>
AVX2_INLINE I decoded(I e) {
  if constexpr (bits >= 15) return decode_h(e);
  const I mid = _mm256_srli_epi32(_mm256_add_epi32(_mm256_slli_epi32(e, 16), i32(0x8000)), bits);
  I r = select(_mm256_cmpeq_epi32(e, i32((1 << bits) - 1)), i32(0xFFFF), mid);
  r = _mm256_andnot_si256(_mm256_cmpeq_epi32(e, _mm256_setzero_si256()), r);
  return decode_h(r);
}

// quantize_endpoint of bc6h_fast.cpp, lane-wise, for `bits` the same in every lane.
template <int bits>
AVX2_INLINE I quantize_endpoint(F target, I cap) {
  const I maxv = i32((1 << bits) - 1);
  const F c = _mm256_mul_ps(target, f32(64.0f / 31.0f));
  I e = _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_mul_ps(c, f32(float(1 << bits))), f32(1.0f / 65536.0f)));
  e = _mm256_min_epi32(_mm256_max_epi32(e, _mm256_setzero_si256()), maxv);
  const I h_up = decoded<bits>(_mm256_add_epi32(e, i32(1))), h_e = decoded<bits>(e);
  const F dn = fabs8(_mm256_sub_ps(_mm256_cvtepi32_ps(h_up), target));
  const F de = fabs8(_mm256_sub_ps(_mm256_cvtepi32_ps(h_e), target));
  const I inc = _mm256_and_si256(_mm256_cmpgt_epi32(maxv, e), as_i(lt(dn, de)));
  e = _mm256_sub_epi32(e, inc);  // inc is −1 where the upper candidate is nearer
  I h = select(inc, h_up, h_e);
  for (;;) {  // while (e > 0 && decoded(e) > cap) --e, in the lanes that need it
    const I need = _mm256_and_si256(_mm256_cmpgt_epi32(e, _mm256_setzero_si256()), _mm256_cmpgt_epi32(h, cap));
    if (!any(need)) return e;
    e = _mm256_add_epi32(e, need);
    h = decoded<bits>(e);
  }
}

// Eight blocks' fit state: channel planes (texel t of lane l at [c][t] lane l).
struct Lanes {
  F H[3][16], W[3][16];
  F vmask[16];
  I cap[3];
  F capf[3];
};

struct Ends {
  I m;        // index into the mode tables
  I e[2][3];  // quantised endpoints
};

// One mode of quantize(): the lanes not yet placed whose delta fits in mode m take it.
template <int m>
AVX2_INLINE void try_mode(const Lanes& L, const F a[3], const F b[3], F spread, I& chosen, Ends& ep) {
  constexpr int lim = (1 << (kDelta[m] - 1)) - 1;
  const F skip = _mm256_cmp_ps(spread, f32(float((lim + 2) << (16 - kEpb[m]))), _CMP_GT_OQ);
  I fits = _mm256_andnot_si256(_mm256_or_si256(chosen, as_i(skip)), i32(-1));
  if (!any(fits)) return;
  I q[2][3];
  for (int c = 0; c < 3; ++c) {
    q[0][c] = quantize_endpoint<kEpb[m]>(a[c], L.cap[c]);
    q[1][c] = quantize_endpoint<kEpb[m]>(b[c], L.cap[c]);
    const I d = _mm256_sub_epi32(q[1][c], q[0][c]);
    fits = _mm256_andnot_si256(_mm256_or_si256(_mm256_cmpgt_epi32(d, i32(lim)), _mm256_cmpgt_epi32(i32(-lim), d)), fits);
  }
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 2; ++k) ep.e[k][c] = select(fits, q[k][c], ep.e[k][c]);
  ep.m = select(fits, i32(m), ep.m);
  chosen = _mm256_or_si256(chosen, fits);
}

// quantize() of bc6h_fast.cpp: the most precise mode whose delta fits, else 10-bit absolute.
AVX2_INLINE Ends quantize(const Lanes& L, const F a[3], const F b[3]) {
  F spread = _mm256_setzero_ps();
  for (int c = 0; c < 3; ++c) {
    const F s = _mm256_mul_ps(fabs8(_mm256_sub_ps(b[c], a[c])), f32(64.0f / 31.0f));
    spread = select(lt(spread, s), s, spread);
  }
  Ends ep;
  ep.m = i32(3);
  for (int c = 0; c < 3; ++c) ep.e[0][c] = ep.e[1][c] = _mm256_setzero_si256();
  I chosen = _mm256_setzero_si256();
  try_mode<0>(L, a, b, spread, chosen, ep);
  try_mode<1>(L, a, b, spread, chosen, ep);
  try_mode<2>(L, a, b, spread, chosen, ep);
  if (_mm256_movemask_ps(as_f(chosen)) != 0xFF)
    for (int c = 0; c < 3; ++c) {
      ep.e[0][c] = select(chosen, ep.e[0][c], quantize_endpoint<10>(a[c], L.cap[c]));
      ep.e[1][c] = select(chosen, ep.e[1][c], quantize_endpoint<10>(b[c], L.cap[c]));
    }
  return ep;
}

AVX2_INLINE I epb_of(I m) {
  return _mm256_permutevar8x32_epi32(_mm256_setr_epi32(kEpb[0], kEpb[1], kEpb[2], kEpb[3], 0, 0, 0, 0), m);
}

// kW4[k] for each lane's k in 0..15.
AVX2_INLINE I weight_of(I k) {
  const I lo = _mm256_setr_epi32(0, 4, 9, 13, 17, 21, 26, 30), hi = _mm256_setr_epi32(34, 38, 43, 47, 51, 55, 60, 64);
  return select(_mm256_cmpgt_epi32(k, i32(7)), _mm256_permutevar8x32_epi32(hi, k), _mm256_permutevar8x32_epi32(lo, k));
}

// A palette entry's decoded half bits (as a float) for weight w: a·64 + 32 + (b − a)·w, >> 6,
// then the decoder's (c·31) >> 6 — the one-block code's integers.
AVX2_INLINE F entry(I a64p32, I diff, I w) {
  const I c = _mm256_srli_epi32(_mm256_add_epi32(a64p32, _mm256_mullo_epi32(diff, w)), 6);
  return _mm256_cvtepi32_ps(decode_h(c));
}

// kNearest of bc6h_fast.cpp (the palette index nearest to position p = 128·t, ties to the lower)
// without a table: e = ⌊15p/128⌋ is the answer or one below it (checked for every p in 0..128),
// and the answer is e + 1 exactly when p lies past the midpoint kW4[e] + kW4[e+1].
AVX2_INLINE I nearest_index(I p) {
  const I e = _mm256_srli_epi32(_mm256_sub_epi32(_mm256_slli_epi32(p, 4), p), 7);
  const I lo = _mm256_setr_epi32(4, 13, 22, 30, 38, 47, 56, 64), hi = _mm256_setr_epi32(72, 81, 90, 98, 106, 115, 124, 999);
  const I mid = select(_mm256_cmpgt_epi32(e, i32(7)), _mm256_permutevar8x32_epi32(hi, e), _mm256_permutevar8x32_epi32(lo, e));
  return _mm256_sub_epi32(e, _mm256_cmpgt_epi32(p, mid));
}

// assign() of bc6h_fast.cpp: indices by weighted projection, then the better neighbour; returns
// each lane's weighted squared error.
AVX2_INLINE F assign(const Lanes& L, const Ends& ep, I idx[16]) {
  const I bits = epb_of(ep.m);
  I a64p32[3], diff[3];
  F P0[3], d[3];
  for (int c = 0; c < 3; ++c) {
    const I ua = unquantize(ep.e[0][c], bits), ub = unquantize(ep.e[1][c], bits);
    a64p32[c] = _mm256_add_epi32(_mm256_slli_epi32(ua, 6), i32(32));
    diff[c] = _mm256_sub_epi32(ub, ua);
    P0[c] = entry(a64p32[c], diff[c], _mm256_setzero_si256());
    d[c] = _mm256_sub_ps(entry(a64p32[c], diff[c], i32(64)), P0[c]);
  }
  const F zero = _mm256_setzero_ps(), one = f32(1.0f), k128 = f32(128.0f);
  F total = zero;
  for (int t = 0; t < 16; ++t) {
    const F wd0 = _mm256_mul_ps(L.W[0][t], d[0]), wd1 = _mm256_mul_ps(L.W[1][t], d[1]), wd2 = _mm256_mul_ps(L.W[2][t], d[2]);
    const F num = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(wd0, _mm256_sub_ps(L.H[0][t], P0[0])),
                                              _mm256_mul_ps(wd1, _mm256_sub_ps(L.H[1][t], P0[1]))),
                                _mm256_mul_ps(wd2, _mm256_sub_ps(L.H[2][t], P0[2])));
    const F den = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(wd0, d[0]), _mm256_mul_ps(wd1, d[1])), _mm256_mul_ps(wd2, d[2]));
    const F safe = select(_mm256_cmp_ps(den, zero, _CMP_GT_OQ), den, one);
    const F p = _mm256_min_ps(_mm256_max_ps(_mm256_div_ps(_mm256_mul_ps(k128, num), safe), zero), k128);
    I pos = _mm256_cvttps_epi32(_mm256_add_ps(p, f32(0.5f)));
    const I k = nearest_index(pos);
    const I km = _mm256_add_epi32(k, _mm256_cmpgt_epi32(k, _mm256_setzero_si256()));
    const I kp = _mm256_sub_epi32(k, _mm256_cmpgt_epi32(i32(15), k));
    F err[3];
    const I ks[3] = {k, km, kp};
    for (int j = 0; j < 3; ++j) {
      const I w = weight_of(ks[j]);
      const F e0 = _mm256_sub_ps(entry(a64p32[0], diff[0], w), L.H[0][t]);
      const F e1 = _mm256_sub_ps(entry(a64p32[1], diff[1], w), L.H[1][t]);
      const F e2 = _mm256_sub_ps(entry(a64p32[2], diff[2], w), L.H[2][t]);
      err[j] = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(L.W[0][t], e0), e0),
                                           _mm256_mul_ps(_mm256_mul_ps(L.W[1][t], e1), e1)),
                             _mm256_mul_ps(_mm256_mul_ps(L.W[2][t], e2), e2));
    }
    const F m1 = lt(err[1], err[0]);
    I kb = select(as_i(m1), km, k);
    F best = select(m1, err[1], err[0]);
    const F m2 = lt(err[2], best);
    kb = select(as_i(m2), kp, kb);
    best = select(m2, err[2], best);
    idx[t] = kb;
    total = _mm256_add_ps(total, best);
  }
  return total;
}

// refit() of bc6h_fast.cpp: least-squares endpoints for the indices; returns the lanes where
// every channel's system was solvable (a, b are meaningful only there).
AVX2_INLINE I refit(const Lanes& L, const I idx[16], F a[3], F b[3]) {
  F g[16];
  for (int t = 0; t < 16; ++t) g[t] = _mm256_mul_ps(_mm256_cvtepi32_ps(weight_of(idx[t])), f32(1.0f / 64.0f));
  const F one = f32(1.0f), zero = _mm256_setzero_ps();
  F ok = as_f(i32(-1));
  for (int c = 0; c < 3; ++c) {
    // Four partial sums (texels t mod 4), added as the one-block code adds its four lanes.
    F p00[4], p01[4], p11[4], q0[4], q1[4];
    for (int l = 0; l < 4; ++l) {
      p00[l] = p01[l] = p11[l] = q0[l] = q1[l] = zero;
      for (int t = l; t < 16; t += 4) {
        const F gg = g[t], w = L.W[c][t], hh = L.H[c][t];
        const F om = _mm256_sub_ps(one, gg), wa = _mm256_mul_ps(w, om), wb = _mm256_mul_ps(w, gg);
        p00[l] = _mm256_add_ps(p00[l], _mm256_mul_ps(wa, om));
        p01[l] = _mm256_add_ps(p01[l], _mm256_mul_ps(wa, gg));
        p11[l] = _mm256_add_ps(p11[l], _mm256_mul_ps(wb, gg));
        q0[l] = _mm256_add_ps(q0[l], _mm256_mul_ps(wa, hh));
        q1[l] = _mm256_add_ps(q1[l], _mm256_mul_ps(wb, hh));
      }
    }
    const F s00 = _mm256_add_ps(_mm256_add_ps(p00[0], p00[1]), _mm256_add_ps(p00[2], p00[3]));
    const F s01 = _mm256_add_ps(_mm256_add_ps(p01[0], p01[1]), _mm256_add_ps(p01[2], p01[3]));
    const F s11 = _mm256_add_ps(_mm256_add_ps(p11[0], p11[1]), _mm256_add_ps(p11[2], p11[3]));
    const F t0 = _mm256_add_ps(_mm256_add_ps(q0[0], q0[1]), _mm256_add_ps(q0[2], q0[3]));
    const F t1 = _mm256_add_ps(_mm256_add_ps(q1[0], q1[1]), _mm256_add_ps(q1[2], q1[3]));
    const F s0011 = _mm256_mul_ps(s00, s11);
    const F det = _mm256_sub_ps(s0011, _mm256_mul_ps(s01, s01));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(fabs8(det), _mm256_mul_ps(f32(1e-6f), _mm256_add_ps(s0011, f32(1e-30f))), _CMP_GT_OQ));
    F va = _mm256_div_ps(_mm256_sub_ps(_mm256_mul_ps(t0, s11), _mm256_mul_ps(s01, t1)), det);
    F vb = _mm256_div_ps(_mm256_sub_ps(_mm256_mul_ps(s00, t1), _mm256_mul_ps(s01, t0)), det);
    // One endpoint past the cap: held at it, the other solved again (as the one-block code).
    const F cp = L.capf[c];
    const F over_a = _mm256_cmp_ps(va, cp, _CMP_GT_OQ), over_b = _mm256_cmp_ps(vb, cp, _CMP_GT_OQ);
    if (any(_mm256_or_ps(over_a, over_b))) {
      const F only_b = _mm256_andnot_ps(over_a, over_b), only_a = _mm256_andnot_ps(over_b, over_a);
      const F sa = _mm256_div_ps(_mm256_sub_ps(t0, _mm256_mul_ps(s01, cp)), s00);
      const F sb = _mm256_div_ps(_mm256_sub_ps(t1, _mm256_mul_ps(s01, cp)), s11);
      va = select(only_b, sa, select(only_a, cp, va));
      vb = select(only_b, cp, select(only_a, sb, vb));
    }
    // std::clamp(v, 0, cap): v < 0 → 0, cap < v → cap.
    a[c] = select(lt(va, zero), zero, select(lt(cp, va), cp, va));
    b[c] = select(lt(vb, zero), zero, select(lt(cp, vb), cp, vb));
  }
  return as_i(ok);
}

// Transposes an 8×8 matrix of floats held as eight rows.
AVX2_INLINE void transpose8(F r[8]) {
  const F t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
  const F t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
  const F t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
  const F t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
  const F u0 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)), u1 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
  const F u2 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)), u3 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  const F u4 = _mm256_shuffle_ps(t4, t6, _MM_SHUFFLE(1, 0, 1, 0)), u5 = _mm256_shuffle_ps(t4, t6, _MM_SHUFFLE(3, 2, 3, 2));
  const F u6 = _mm256_shuffle_ps(t5, t7, _MM_SHUFFLE(1, 0, 1, 0)), u7 = _mm256_shuffle_ps(t5, t7, _MM_SHUFFLE(3, 2, 3, 2));
  r[0] = _mm256_permute2f128_ps(u0, u4, 0x20), r[1] = _mm256_permute2f128_ps(u1, u5, 0x20);
  r[2] = _mm256_permute2f128_ps(u2, u6, 0x20), r[3] = _mm256_permute2f128_ps(u3, u7, 0x20);
  r[4] = _mm256_permute2f128_ps(u0, u4, 0x31), r[5] = _mm256_permute2f128_ps(u1, u5, 0x31);
  r[6] = _mm256_permute2f128_ps(u2, u6, 0x31), r[7] = _mm256_permute2f128_ps(u3, u7, 0x31);
}

// Sum of 16 lane vectors as sum16 of bc6h_fast.cpp adds 16 floats.
AVX2_INLINE F sum16(const F v[16]) {
  F l[4];
  for (int i = 0; i < 4; ++i) l[i] = _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_setzero_ps(), v[i]), v[i + 4]), v[i + 8]), v[i + 12]);
  return _mm256_add_ps(_mm256_add_ps(l[0], l[1]), _mm256_add_ps(l[2], l[3]));
}

}  // namespace

AVX2_FN void encode_blocks_fast_x8_err(const uint16_t* const h[8], const float* const x[8],
                                       const uint8_t* const valid[8], uint8_t* const out[8], float err_out[8]) {
  Lanes L;
  bool all_valid = true;
  for (int l = 0; l < 8; ++l) {
    uint64_t v[2];
    std::memcpy(v, valid[l], 16);
    all_valid &= (v[0] & v[1]) == 0x0101010101010101ull;
  }
  if (all_valid) {
    // Every texel real (inner blocks): half bits and values as 8×48 matrices (lane, t·3 + c)
    // transposed by 8×8 blocks of columns into the channel planes.
#pragma GCC unroll 6
    for (int j = 0; j < 48; j += 8) {
      F hv[8], xv[8];
      for (int l = 0; l < 8; ++l) {
        hv[l] = _mm256_cvtepi32_ps(_mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(h[l] + j))));
        xv[l] = _mm256_loadu_ps(x[l] + j);
      }
      transpose8(hv);
      transpose8(xv);
#pragma GCC unroll 8
      for (int i = 0; i < 8; ++i) L.H[(j + i) % 3][(j + i) / 3] = hv[i], L.W[(j + i) % 3][(j + i) / 3] = xv[i];
    }
    for (int t = 0; t < 16; ++t) L.vmask[t] = f32(1.0f);
  } else {
    alignas(32) float H[3][16][8], X[3][16][8], V[16][8];
    for (int l = 0; l < 8; ++l) {
      int first = 0;
      while (first < 15 && !valid[l][first]) ++first;
      for (int t = 0; t < 16; ++t) {
        const int s = valid[l][t] ? t : first;
        V[t][l] = valid[l][t] ? 1.0f : 0.0f;
        for (int c = 0; c < 3; ++c) H[c][t][l] = float(h[l][s * 3 + c]), X[c][t][l] = x[l][s * 3 + c];
      }
    }
    for (int t = 0; t < 16; ++t) {
      L.vmask[t] = _mm256_load_ps(V[t]);
      for (int c = 0; c < 3; ++c) L.H[c][t] = _mm256_load_ps(H[c][t]), L.W[c][t] = _mm256_load_ps(X[c][t]);
    }
  }
  F lo[3], hi[3];
  for (int c = 0; c < 3; ++c) {
    lo[c] = hi[c] = L.H[c][0];
    for (int t = 0; t < 16; ++t) {
      const F W = L.W[c][t];
      const F xv = select(lt(W, f32(0.25f)), f32(0.25f), W);
      const F slope = _mm256_div_ps(xv, _mm256_add_ps(f32(1.0f), xv));
      L.W[c][t] = _mm256_mul_ps(_mm256_mul_ps(slope, slope), L.vmask[t]);
      lo[c] = _mm256_min_ps(lo[c], L.H[c][t]), hi[c] = _mm256_max_ps(hi[c], L.H[c][t]);
    }
    L.cap[c] = _mm256_add_epi32(_mm256_cvttps_epi32(hi[c]), i32(1));
    L.capf[c] = _mm256_cvtepi32_ps(L.cap[c]);
  }
  F tw[16];
  for (int t = 0; t < 16; ++t)
    tw[t] = _mm256_mul_ps(_mm256_add_ps(_mm256_add_ps(L.W[0][t], L.W[1][t]), L.W[2][t]), f32(1.0f / 3.0f));
  const F wsum = sum16(tw);
  const F solid = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(lo[0], hi[0], _CMP_EQ_OQ), _mm256_cmp_ps(lo[1], hi[1], _CMP_EQ_OQ)),
                                _mm256_cmp_ps(lo[2], hi[2], _CMP_EQ_OQ));

  // Principal axis (power iteration from the covariance's diagonal).
  F mean[3], tmp[16];
  for (int c = 0; c < 3; ++c) {
    for (int t = 0; t < 16; ++t) tmp[t] = _mm256_mul_ps(tw[t], L.H[c][t]);
    mean[c] = _mm256_div_ps(sum16(tmp), wsum);
  }
  F cov[6];
  {
    F dd[3][16];
    for (int c = 0; c < 3; ++c)
      for (int t = 0; t < 16; ++t) dd[c][t] = _mm256_sub_ps(L.H[c][t], mean[c]);
    const int pi[6] = {0, 1, 2, 0, 0, 1}, pj[6] = {0, 1, 2, 1, 2, 2};
    for (int i = 0; i < 6; ++i) {
      for (int t = 0; t < 16; ++t) tmp[t] = _mm256_mul_ps(_mm256_mul_ps(tw[t], dd[pi[i]][t]), dd[pj[i]][t]);
      cov[i] = sum16(tmp);
    }
  }
  F ax[3] = {cov[0], cov[1], cov[2]};
  F going = as_f(i32(-1));
  for (int it = 0; it < 4; ++it) {
    const F v0 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(cov[0], ax[0]), _mm256_mul_ps(cov[3], ax[1])), _mm256_mul_ps(cov[4], ax[2]));
    const F v1 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(cov[3], ax[0]), _mm256_mul_ps(cov[1], ax[1])), _mm256_mul_ps(cov[5], ax[2]));
    const F v2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(cov[4], ax[0]), _mm256_mul_ps(cov[5], ax[1])), _mm256_mul_ps(cov[2], ax[2]));
    const F m = _mm256_max_ps(_mm256_max_ps(fabs8(v0), fabs8(v1)), fabs8(v2));
    going = _mm256_and_ps(going, _mm256_cmp_ps(m, _mm256_setzero_ps(), _CMP_GT_OQ));  // once stopped, stays
    if (!any(going)) break;
    ax[0] = select(going, _mm256_div_ps(v0, m), ax[0]);
    ax[1] = select(going, _mm256_div_ps(v1, m), ax[1]);
    ax[2] = select(going, _mm256_div_ps(v2, m), ax[2]);
  }
  F len2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax[0], ax[0]), _mm256_mul_ps(ax[1], ax[1])), _mm256_mul_ps(ax[2], ax[2]));
  {
    const F flat = _mm256_cmp_ps(len2, _mm256_setzero_ps(), _CMP_NGT_UQ);  // !(len2 > 0)
    for (int c = 0; c < 3; ++c) ax[c] = select(flat, f32(1.0f), ax[c]);
    len2 = select(flat, f32(3.0f), len2);
  }
  F tmin = f32(1e30f), tmax = f32(-1e30f);
  for (int t = 0; t < 16; ++t) {
    const F p = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_sub_ps(L.H[0][t], mean[0]), ax[0]),
                                            _mm256_mul_ps(_mm256_sub_ps(L.H[1][t], mean[1]), ax[1])),
                              _mm256_mul_ps(_mm256_sub_ps(L.H[2][t], mean[2]), ax[2]));
    const F v = _mm256_cmp_ps(L.vmask[t], _mm256_setzero_ps(), _CMP_NEQ_OQ);
    tmin = select(_mm256_and_ps(v, lt(p, tmin)), p, tmin);
    tmax = select(_mm256_and_ps(v, lt(tmax, p)), p, tmax);
  }
  F a[3], b[3];
  for (int c = 0; c < 3; ++c) {
    const F va = _mm256_add_ps(mean[c], _mm256_mul_ps(_mm256_div_ps(tmin, len2), ax[c]));
    const F vb = _mm256_add_ps(mean[c], _mm256_mul_ps(_mm256_div_ps(tmax, len2), ax[c]));
    // std::clamp(v, lo, hi)
    a[c] = select(lt(va, lo[c]), lo[c], select(lt(hi[c], va), hi[c], va));
    b[c] = select(lt(vb, lo[c]), lo[c], select(lt(hi[c], vb), hi[c], vb));
  }

  Ends best = quantize(L, a, b);
  I idx[16];
  F best_err = assign(L, best, idx);
  I active = as_i(_mm256_andnot_ps(solid, as_f(i32(-1))));
  for (int pass = 0; pass < 2; ++pass) {
    active = _mm256_and_si256(active, as_i(_mm256_cmp_ps(best_err, _mm256_setzero_ps(), _CMP_GT_OQ)));
    if (!any(active)) break;
    active = _mm256_and_si256(active, refit(L, idx, a, b));
    if (!any(active)) break;
    const Ends ep = quantize(L, a, b);
    // A lane whose endpoints did not change would get the same error, which is not lower: it
    // stops here as the one-block loop does, and the index step is skipped when no lane is left.
    I same = _mm256_cmpeq_epi32(ep.m, best.m);
    for (int k = 0; k < 2; ++k)
      for (int c = 0; c < 3; ++c) same = _mm256_and_si256(same, _mm256_cmpeq_epi32(ep.e[k][c], best.e[k][c]));
    active = _mm256_andnot_si256(same, active);
    if (!any(active)) break;
    I trial[16];
    const F err = assign(L, ep, trial);
    active = _mm256_and_si256(active, as_i(lt(err, best_err)));
    best.m = select(active, ep.m, best.m);
    for (int k = 0; k < 2; ++k)
      for (int c = 0; c < 3; ++c) best.e[k][c] = select(active, ep.e[k][c], best.e[k][c]);
    for (int t = 0; t < 16; ++t) idx[t] = select(active, trial[t], idx[t]);
    best_err = select(as_f(active), err, best_err);
  }

  if (err_out) _mm256_storeu_ps(err_out, _mm256_andnot_ps(solid, best_err));  // solid: exact, 0

  // Each lane's indices as nibbles (texel t at bits 4t): two 32-bit words per lane.
  I nib_lo = idx[0], nib_hi = idx[8];
  for (int t = 1; t < 8; ++t) {
    nib_lo = _mm256_or_si256(nib_lo, _mm256_slli_epi32(idx[t], 4 * t));
    nib_hi = _mm256_or_si256(nib_hi, _mm256_slli_epi32(idx[t + 8], 4 * t));
  }
  alignas(32) int m[8], e[2][3][8], hb[3][8];
  alignas(32) unsigned nl[8], nh[8];
  _mm256_store_si256(reinterpret_cast<I*>(m), best.m);
  for (int k = 0; k < 2; ++k)
    for (int c = 0; c < 3; ++c) _mm256_store_si256(reinterpret_cast<I*>(e[k][c]), best.e[k][c]);
  _mm256_store_si256(reinterpret_cast<I*>(nl), nib_lo);
  _mm256_store_si256(reinterpret_cast<I*>(nh), nib_hi);
  for (int c = 0; c < 3; ++c) _mm256_store_si256(reinterpret_cast<I*>(hb[c]), _mm256_cvttps_epi32(hi[c]));
  const int solid_bits = _mm256_movemask_ps(solid);
  for (int l = 0; l < 8; ++l) {
    if (!out[l]) continue;
    int ends[2][3];
    if ((solid_bits >> l) & 1) {  // mode 14 with both endpoints the exact 16-bit value, indices 0
      for (int c = 0; c < 3; ++c) ends[0][c] = ends[1][c] = (hb[c][l] * 64 + 30) / 31;
      pack_one_region(kModeNumber[0], ends, 0, out[l]);
      continue;
    }
    for (int k = 0; k < 2; ++k)
      for (int c = 0; c < 3; ++c) ends[k][c] = e[k][c][l];
    pack_one_region(kModeNumber[m[l]], ends, uint64_t(nl[l]) | uint64_t(nh[l]) << 32, out[l]);
  }
}

void encode_blocks_fast_x8(const uint16_t* const h[8], const float* const x[8], const uint8_t* const valid[8],
                           uint8_t* const out[8]) {
  encode_blocks_fast_x8_err(h, x, valid, out, nullptr);
}

bool cpu_has_avx2() {
  static const bool has = [] {
    unsigned a = 0, b = 0, c = 0, d = 0;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return false;
    if (!(c & (1u << 27)) || !(c & (1u << 28))) return false;  // OSXSAVE, AVX
    unsigned lo = 0, hi = 0;
    __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    if ((lo & 6u) != 6u) return false;  // XMM and YMM state enabled by the OS
    if (__get_cpuid_max(0, nullptr) < 7) return false;
    __cpuid_count(7, 0, a, b, c, d);
    return (b & (1u << 5)) != 0;  // AVX2
  }();
  return has;
}

}  // namespace ahd::bc6h

#else

namespace ahd::bc6h {
void encode_blocks_fast_x8(const uint16_t* const*, const float* const*, const uint8_t* const*, uint8_t* const*) {}
void encode_blocks_fast_x8_err(const uint16_t* const*, const float* const*, const uint8_t* const*, uint8_t* const*,
                               float*) {}
bool cpu_has_avx2() { return false; }
}  // namespace ahd::bc6h

#endif

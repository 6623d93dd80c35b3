// The one-region fit of `fast` (and `default`'s incumbent), sixteen blocks at a time: the fit of
// bc6h_fast_lanes.inc with one block per AVX-512 lane (mask registers for the lanes' branches,
// one permute for each 16-entry table), the same operations as the AVX2 and one-block paths in
// the same order, so the same fits, error included (tested with each path forced).
//
// Built for plain x86-64 as bc6h_fast_avx2.cpp is: only the functions here carry the AVX-512
// target attribute, and bc6h_fast.cpp calls them only when the CPU and the OS support AVX-512
// F/VL/BW/DQ (cpu::has(cpu::kAvx512)).
#include "codecs/bc6h/bc6h_fast.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// GCC 12's AVX-512 intrinsics start their unmasked forms from _mm512_undefined_*(), which its
// -Wuninitialized reports once per inlined use (a known false positive of the header).
#pragma GCC diagnostic ignored "-Wuninitialized"
#ifndef __clang__  // clang has no such group (and warns on an unknown one)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <cstring>

namespace ahd::bc6h {

namespace {

#define AVX512_TARGET "avx2,avx512f,avx512vl,avx512bw,avx512dq"
#define LANE_INLINE __attribute__((target(AVX512_TARGET), always_inline)) inline
#define AVX512_FN __attribute__((target(AVX512_TARGET)))

constexpr int N = 16;
using F = __m512;
using I = __m512i;
using M = __mmask16;

LANE_INLINE F f32(float v) { return _mm512_set1_ps(v); }
LANE_INLINE I i32(int v) { return _mm512_set1_epi32(v); }
LANE_INLINE F fzero() { return _mm512_setzero_ps(); }
LANE_INLINE I izero() { return _mm512_setzero_si512(); }
LANE_INLINE F add(F a, F b) { return _mm512_add_ps(a, b); }
LANE_INLINE F sub(F a, F b) { return _mm512_sub_ps(a, b); }
LANE_INLINE F mul(F a, F b) { return _mm512_mul_ps(a, b); }
LANE_INLINE F div(F a, F b) { return _mm512_div_ps(a, b); }
LANE_INLINE F fmin(F a, F b) { return _mm512_min_ps(a, b); }
LANE_INLINE F fmax(F a, F b) { return _mm512_max_ps(a, b); }
LANE_INLINE F fabsv(F v) { return _mm512_andnot_ps(_mm512_set1_ps(-0.0f), v); }
LANE_INLINE F to_f(I v) { return _mm512_cvtepi32_ps(v); }
LANE_INLINE I trunc_i(F v) { return _mm512_cvttps_epi32(v); }
LANE_INLINE I addi(I a, I b) { return _mm512_add_epi32(a, b); }
LANE_INLINE I subi(I a, I b) { return _mm512_sub_epi32(a, b); }
LANE_INLINE I mini(I a, I b) { return _mm512_min_epi32(a, b); }
LANE_INLINE I maxi(I a, I b) { return _mm512_max_epi32(a, b); }
template <int k>
LANE_INLINE I shl(I v) { return _mm512_slli_epi32(v, k); }
template <int k>
LANE_INLINE I shr(I v) { return _mm512_srli_epi32(v, k); }
LANE_INLINE I shlv(I v, I k) { return _mm512_sllv_epi32(v, k); }
LANE_INLINE I shrv(I v, I k) { return _mm512_srlv_epi32(v, k); }
LANE_INLINE M lt(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
LANE_INLINE M gt(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
LANE_INLINE M eqf(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
LANE_INLINE M neqf(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_NEQ_OQ); }
LANE_INLINE M ngt(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_NGT_UQ); }
LANE_INLINE M eqi(I a, I b) { return _mm512_cmpeq_epi32_mask(a, b); }
LANE_INLINE M gti(I a, I b) { return _mm512_cmpgt_epi32_mask(a, b); }
LANE_INLINE M mand(M a, M b) { return M(a & b); }
LANE_INLINE M mor(M a, M b) { return M(a | b); }
LANE_INLINE M mandn(M a, M b) { return M(~a & b); }
LANE_INLINE M mall() { return M(0xFFFF); }
LANE_INLINE unsigned bits_of(M m) { return unsigned(m); }
LANE_INLINE bool any(M m) { return m != 0; }
LANE_INLINE bool all(M m) { return m == 0xFFFF; }
LANE_INLINE F sel(M m, F yes, F no) { return _mm512_mask_blend_ps(m, no, yes); }
LANE_INLINE I sel(M m, I yes, I no) { return _mm512_mask_blend_epi32(m, no, yes); }
LANE_INLINE I inc_where(M m, I v) { return _mm512_mask_add_epi32(v, m, v, _mm512_set1_epi32(1)); }
LANE_INLINE I dec_where(M m, I v) { return _mm512_mask_sub_epi32(v, m, v, _mm512_set1_epi32(1)); }
LANE_INLINE I table16(const int* tbl, I k) { return _mm512_permutexvar_epi32(k, _mm512_loadu_si512(tbl)); }
LANE_INLINE F ffloor(F v) { return _mm512_roundscale_ps(v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
LANE_INLINE F table16f(const float* tbl, I k) { return _mm512_permutexvar_ps(k, _mm512_loadu_ps(tbl)); }
LANE_INLINE F loadf(const float* p) { return _mm512_load_ps(p); }
LANE_INLINE void storef(float* p, F v) { _mm512_store_ps(p, v); }
LANE_INLINE void storei(int* p, I v) { _mm512_store_si512(p, v); }

#include "codecs/bc6h/bc6h_fast_lanes.inc"

#include "codecs/bc6h/bc6h_transpose8.inc"

// dst with the lanes of `place` (in order) replaced by the lanes of src in `take` (in order).
LANE_INLINE F move_lanes(F dst, M place, F src, M take) { return _mm512_mask_expand_ps(dst, place, _mm512_maskz_compress_ps(take, src)); }
LANE_INLINE I move_lanes(I dst, M place, I src, M take) {
  return _mm512_mask_expand_epi32(dst, place, _mm512_maskz_compress_epi32(take, src));
}

// Moves the lanes `take` of a batch (its planes and new endpoints) to the lanes `place` of the
// gathered batch (sl, sep): one two-source permute per register, its indices computed once.
LANE_INLINE void gather_lanes(Lanes& sl, Ends& sep, M place, const Lanes& bl, const Ends& bep, M take) {
  const I iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  // Lane j of place ← lane (16 + the source lane) of the pair (sl, bl); other lanes keep their own.
  const I ix = _mm512_mask_expand_epi32(iota, place, _mm512_maskz_compress_epi32(take, _mm512_add_epi32(iota, i32(16))));
  for (int c = 0; c < 3; ++c)
    for (int t = 0; t < 16; ++t) {
      sl.H[c][t] = _mm512_permutex2var_ps(sl.H[c][t], ix, bl.H[c][t]);
      sl.W[c][t] = _mm512_permutex2var_ps(sl.W[c][t], ix, bl.W[c][t]);
    }
  sep.m = _mm512_permutex2var_epi32(sep.m, ix, bep.m);
  for (int k = 0; k < 2; ++k)
    for (int c = 0; c < 3; ++c) sep.e[k][c] = _mm512_permutex2var_epi32(sep.e[k][c], ix, bep.e[k][c]);
}

// Loads sixteen blocks into a batch's planes.
LANE_INLINE void load(Lanes& L, const uint16_t* const h[16], const float* const x[16], const uint8_t* const valid[16]) {
  bool all_valid = true;
  for (int l = 0; l < 16; ++l) {
    uint64_t v[2];
    std::memcpy(v, valid[l], 16);
    all_valid &= (v[0] & v[1]) == 0x0101010101010101ull;
  }
  if (!all_valid) return load_partial(L, h, x, valid);
  // Every texel real (inner blocks): the values x, each half of the lanes transposed by 8×8
  // blocks of columns as in the AVX2 path, the two halves joined into one register. The half
  // bits are those of x (the contract of h), converted here with the same rounding as
  // floats_to_half: cheaper than transposing h too (hard's whole encode ≈ 4 % faster).
#pragma GCC unroll 6
  for (int j = 0; j < 48; j += 8) {
    __m256 xv[2][8];
    for (int half = 0; half < 2; ++half) {
      for (int l = 0; l < 8; ++l) xv[half][l] = _mm256_loadu_ps(x[half * 8 + l] + j);
      transpose8(xv[half]);
    }
#pragma GCC unroll 8
    for (int i = 0; i < 8; ++i) {
      const F v = _mm512_insertf32x8(_mm512_castps256_ps512(xv[0][i]), xv[1][i], 1);
      L.W[(j + i) % 3][(j + i) / 3] = v;
      const __m256i hb = _mm512_cvtps_ph(v, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
      L.H[(j + i) % 3][(j + i) / 3] = _mm512_cvtepi32_ps(_mm512_cvtepu16_epi32(hb));
    }
  }
  for (int t = 0; t < 16; ++t) L.vmask[t] = f32(1.0f);
}

// The fits of `batches` batches (block i: h[i], x[i], valid[i]; bit l of real[g]: lane l of
// batch g is a real block, not padding), each batch handed to finish(batch, g) at the end.
template <class Finish>
LANE_INLINE void fit_gathered(int batches, const uint16_t* const h[], const float* const x[], const uint8_t* const valid[],
                              const unsigned real[], Finish finish) {
  // Every batch through its first least-squares pass and its second up to the index step, which
  // then runs on the lanes that need it gathered from all the batches into as few as they fill
  // (a lane's result depends only on its own values, so the fits are the same) instead of on
  // every batch with most of its lanes idle. On the hard image 2 988 of 16 384 blocks need it,
  // in 794 of 1 024 batches: 262 gathered index steps instead of 794 (347 with four batches per
  // call; noisy 1 020 → 406, smooth 155 → 126). Hard's fit runs ≈ 6–9 % faster for it.
  Batch B[kMaxBatches];
  Ends ep[kMaxBatches];
  bool need[kMaxBatches];
  for (int g = 0; g < batches; ++g) {
    load(B[g].L, h + 16 * g, x + 16 * g, valid + 16 * g);
    start(B[g]);
    refine(B[g].L, B[g].s);
    need[g] = refine_head(B[g].L, B[g].s, ep[g]);
  }
  Lanes SL;
  Ends SE;
  std::memset(static_cast<void*>(&SL), 0, sizeof SL);  // idle lanes: zeros (their results unused)
  std::memset(static_cast<void*>(&SE), 0, sizeof SE);
  I trial[kMaxBatches][16];
  F err[kMaxBatches];
  M take[kMaxBatches], place[kMaxBatches];
  int first = 0, filled = 0;  // batches first..g−1 have lanes in S, which holds `filled` lanes
  for (int g = 0; g <= batches; ++g) {
    // Only the lanes of real blocks (a partial batch's padding needs no index step).
    const M t = g < batches && need[g] ? M(B[g].s.active & real[g]) : M(0);
    const int n = __builtin_popcount(t);
    if (filled > 0 && (g == batches || filled + n > 16)) {  // S is full: its index step, results back
      I st[16];
      const F se = assign(SL, SE, st);
      for (int k = first; k < g; ++k) {
        if (!take[k]) continue;
        for (int i = 0; i < 16; ++i) trial[k][i] = move_lanes(izero(), take[k], st[i], place[k]);
        err[k] = move_lanes(fzero(), take[k], se, place[k]);
        B[k].s.active = take[k];
        refine_tail(B[k].s, ep[k], trial[k], err[k]);
      }
      filled = 0;
    }
    if (g == batches) break;
    if (filled == 0) first = g;
    take[g] = t, place[g] = M(((1u << n) - 1) << filled);
    if (n > 0) gather_lanes(SL, SE, place[g], B[g].L, ep[g], t);
    filled += n;
  }
  for (int g = 0; g < batches; ++g) finish(B[g], g);
}

LANE_INLINE I andi(I a, I b) { return _mm512_and_si512(a, b); }
LANE_INLINE I ori(I a, I b) { return _mm512_or_si512(a, b); }

// The low six bits of v in reverse order.
LANE_INLINE I reverse6(I v) {
  const I one = i32(1);
  I r = shl<5>(andi(v, one));
  r = ori(r, shl<3>(andi(v, i32(2)))), r = ori(r, shl<1>(andi(v, i32(4))));
  r = ori(r, shr<1>(andi(v, i32(8)))), r = ori(r, shr<3>(andi(v, i32(16))));
  return ori(r, shr<5>(andi(v, i32(32))));
}

constexpr int kDeltaTable[16] = {4, 8, 9, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
constexpr int kCodeTable[16] = {0x0f, 0x0b, 0x07, 0x03, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};

// Writes every lane's fit as pack_one_region writes the fit finish() gives (solid lanes: mode
// 14, both endpoints (hi·64 + 30) / 31, indices 0; the block mirrored when texel 0's index has
// its top bit set; modes 11–14's fixed layout), as four 32-bit words per lane: block l at
// blocks[l] and its fit error at err[l] (skipped when blocks[l] is null).
LANE_INLINE void finish_packed(const Batch& B, uint8_t* const blocks[16], float* const err[16]) {
  const M solid = B.solid;
  const I m = sel(solid, izero(), B.s.best.m);
  I e[2][3], idx[16];
  for (int c = 0; c < 3; ++c) {
    // (hi·64 + 30) / 31 in float: the numerator is below 2²², so it and the quotient's integer
    // part are exact (a fraction k/31 lies over 1/31 from the next integer, above half an ulp).
    const I v = trunc_i(div(to_f(addi(shl<6>(trunc_i(B.hi[c])), i32(30))), f32(31.0f)));
    e[0][c] = sel(solid, v, B.s.best.e[0][c]), e[1][c] = sel(solid, v, B.s.best.e[1][c]);
  }
  for (int t = 0; t < 16; ++t) idx[t] = sel(solid, izero(), B.s.idx[t]);
  const M mirror = gti(idx[0], i32(7));
  for (int c = 0; c < 3; ++c) {
    const I a = sel(mirror, e[1][c], e[0][c]), b = sel(mirror, e[0][c], e[1][c]);
    e[0][c] = a, e[1][c] = b;
  }
  for (int t = 0; t < 16; ++t) idx[t] = sel(mirror, subi(i32(15), idx[t]), idx[t]);
  const I delta = table16(kDeltaTable, m), high = subi(table16(kEpbTable, m), i32(10));
  const M transformed = gti(i32(3), m);
  const I dmask = subi(shlv(i32(1), delta), i32(1)), lo10 = i32(0x3FF);
  I second[3];
  for (int c = 0; c < 3; ++c) {
    const I d = andi(subi(e[1][c], sel(transformed, e[0][c], izero())), dmask);
    second[c] = ori(d, shlv(shrv(reverse6(shr<10>(e[0][c])), subi(i32(6), high)), delta));
  }
  I w[4];
  w[0] = ori(ori(table16(kCodeTable, m), shl<5>(andi(e[0][0], lo10))),
             ori(shl<15>(andi(e[0][1], lo10)), shl<25>(andi(e[0][2], i32(0x7F)))));
  w[1] = ori(ori(shr<7>(andi(e[0][2], lo10)), shl<3>(second[0])), ori(shl<13>(second[1]), shl<23>(andi(second[2], i32(0x1FF)))));
  w[2] = ori(shr<9>(second[2]), shl<1>(idx[0]));
  w[3] = izero();
  for (int t = 1; t < 8; ++t) w[2] = ori(w[2], _mm512_slli_epi32(idx[t], 4 * t));
  for (int t = 8; t < 16; ++t) w[3] = ori(w[3], _mm512_slli_epi32(idx[t], 4 * (t - 8)));
  alignas(64) uint32_t words[4][16];
  alignas(64) float ev[16];
  for (int k = 0; k < 4; ++k) storei(reinterpret_cast<int*>(words[k]), w[k]);
  storef(ev, sel(solid, fzero(), B.s.best_err));
  for (int l = 0; l < 16; ++l) {
    if (!blocks[l]) continue;
    const uint32_t b[4] = {words[0][l], words[1][l], words[2][l], words[3][l]};
    std::memcpy(blocks[l], b, 16);  // little-endian: x86-64 only
    *err[l] = ev[l];
  }
}

// Per batch of sixteen, the lanes that hold a real block (a non-null destination).
template <class T>
void real_lanes(int batches, T* const dst[], unsigned real[]) {
  for (int g = 0; g < batches; ++g) {
    real[g] = 0;
    for (int l = 0; l < 16; ++l) real[g] |= unsigned(dst[16 * g + l] != nullptr) << l;
  }
}

}  // namespace

AVX512_FN void fit_blocks_fast_x16n(int batches, const uint16_t* const h[], const float* const x[],
                                    const uint8_t* const valid[], OneRegionFit* const out[]) {
  unsigned real[kMaxBatches];
  real_lanes(batches, out, real);
  struct {
    OneRegionFit* const* out;
    LANE_INLINE void operator()(const Batch& B, int g) const { finish(B, out + 16 * g); }
  } fin{out};
  fit_gathered(batches, h, x, valid, real, fin);
}

AVX512_FN void encode_blocks_fast_x16n(int batches, const uint16_t* const h[], const float* const x[],
                                       const uint8_t* const valid[], uint8_t* const blocks[], float* const err[]) {
  unsigned real[kMaxBatches];
  real_lanes(batches, blocks, real);
  struct {
    uint8_t* const* blocks;
    float* const* err;
    LANE_INLINE void operator()(const Batch& B, int g) const { finish_packed(B, blocks + 16 * g, err + 16 * g); }
  } fin{blocks, err};
  fit_gathered(batches, h, x, valid, real, fin);
}

}  // namespace ahd::bc6h

#else

namespace ahd::bc6h {
void fit_blocks_fast_x16n(int, const uint16_t* const*, const float* const*, const uint8_t* const*, OneRegionFit* const*) {}
void encode_blocks_fast_x16n(int, const uint16_t* const*, const float* const*, const uint8_t* const*, uint8_t* const*,
                             float* const*) {}
}  // namespace ahd::bc6h

#endif

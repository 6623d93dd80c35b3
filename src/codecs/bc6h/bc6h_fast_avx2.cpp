// The one-region fit of `fast` (and `default`'s incumbent), eight blocks at a time: the fit of
// fit_one_region_fast (bc6h_fast.cpp) with one block per AVX2 lane, so that the per-block scalar
// work (the principal axis, the endpoint quantisation with its mode choice and cap, the
// least-squares solve) and the palette lookups of the index step (per-texel gathers in the
// one-block code) become lane-wise arithmetic. The fit itself is bc6h_fast_lanes.inc, shared with
// the 16-lane AVX-512 batches (bc6h_fast_avx512.cpp); this file gives it AVX2 lanes, whose masks
// are all-ones / all-zeros int lanes, and loads eight blocks into them.
//
// Built for plain x86-64: only the functions here are compiled for AVX2 (target attribute, no
// per-file flags, so no inline function of a shared header is ever compiled with AVX2), and
// bc6h_fast.cpp calls them only when the CPU reports AVX2 (cpu::has(cpu::kAvx2)).
#include "codecs/bc6h/bc6h_fast.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include <cstring>

namespace ahd::bc6h {

namespace {

#define LANE_INLINE __attribute__((target("avx2"), always_inline)) inline
#define AVX2_FN __attribute__((target("avx2")))

constexpr int N = 8;
using F = __m256;
using I = __m256i;
using M = __m256i;  // all ones in a lane that is set

LANE_INLINE F f32(float v) { return _mm256_set1_ps(v); }
LANE_INLINE I i32(int v) { return _mm256_set1_epi32(v); }
LANE_INLINE F fzero() { return _mm256_setzero_ps(); }
LANE_INLINE I izero() { return _mm256_setzero_si256(); }
LANE_INLINE F add(F a, F b) { return _mm256_add_ps(a, b); }
LANE_INLINE F sub(F a, F b) { return _mm256_sub_ps(a, b); }
LANE_INLINE F mul(F a, F b) { return _mm256_mul_ps(a, b); }
LANE_INLINE F div(F a, F b) { return _mm256_div_ps(a, b); }
LANE_INLINE F fmin(F a, F b) { return _mm256_min_ps(a, b); }
LANE_INLINE F fmax(F a, F b) { return _mm256_max_ps(a, b); }
LANE_INLINE F fabsv(F v) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), v); }
LANE_INLINE F to_f(I v) { return _mm256_cvtepi32_ps(v); }
LANE_INLINE I trunc_i(F v) { return _mm256_cvttps_epi32(v); }
LANE_INLINE I addi(I a, I b) { return _mm256_add_epi32(a, b); }
LANE_INLINE I subi(I a, I b) { return _mm256_sub_epi32(a, b); }
LANE_INLINE I mini(I a, I b) { return _mm256_min_epi32(a, b); }
LANE_INLINE I maxi(I a, I b) { return _mm256_max_epi32(a, b); }
template <int k>
LANE_INLINE I shl(I v) { return _mm256_slli_epi32(v, k); }
template <int k>
LANE_INLINE I shr(I v) { return _mm256_srli_epi32(v, k); }
LANE_INLINE I shlv(I v, I k) { return _mm256_sllv_epi32(v, k); }
LANE_INLINE I shrv(I v, I k) { return _mm256_srlv_epi32(v, k); }
LANE_INLINE M lt(F a, F b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_LT_OQ)); }
LANE_INLINE M gt(F a, F b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_GT_OQ)); }
LANE_INLINE M eqf(F a, F b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_EQ_OQ)); }
LANE_INLINE M neqf(F a, F b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_NEQ_OQ)); }
LANE_INLINE M ngt(F a, F b) { return _mm256_castps_si256(_mm256_cmp_ps(a, b, _CMP_NGT_UQ)); }
LANE_INLINE M eqi(I a, I b) { return _mm256_cmpeq_epi32(a, b); }
LANE_INLINE M gti(I a, I b) { return _mm256_cmpgt_epi32(a, b); }
LANE_INLINE M mand(M a, M b) { return _mm256_and_si256(a, b); }
LANE_INLINE M mor(M a, M b) { return _mm256_or_si256(a, b); }
LANE_INLINE M mandn(M a, M b) { return _mm256_andnot_si256(a, b); }
LANE_INLINE M mall() { return _mm256_set1_epi32(-1); }
LANE_INLINE unsigned bits_of(M m) { return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(m))); }
LANE_INLINE bool any(M m) { return bits_of(m) != 0; }
LANE_INLINE bool all(M m) { return bits_of(m) == 0xFFu; }
LANE_INLINE F sel(M m, F yes, F no) { return _mm256_blendv_ps(no, yes, _mm256_castsi256_ps(m)); }
LANE_INLINE I sel(M m, I yes, I no) { return _mm256_blendv_epi8(no, yes, m); }
LANE_INLINE I inc_where(M m, I v) { return _mm256_sub_epi32(v, m); }  // m is −1 where set
LANE_INLINE I dec_where(M m, I v) { return _mm256_add_epi32(v, m); }
LANE_INLINE I table16(const int* tbl, I k) {
  const I lo = _mm256_loadu_si256(reinterpret_cast<const I*>(tbl)), hi = _mm256_loadu_si256(reinterpret_cast<const I*>(tbl + 8));
  return sel(gti(k, i32(7)), _mm256_permutevar8x32_epi32(hi, k), _mm256_permutevar8x32_epi32(lo, k));
}
LANE_INLINE F ffloor(F v) { return _mm256_round_ps(v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
LANE_INLINE F table16f(const float* tbl, I k) {
  const F lo = _mm256_loadu_ps(tbl), hi = _mm256_loadu_ps(tbl + 8);
  return sel(gti(k, i32(7)), _mm256_permutevar8x32_ps(hi, k), _mm256_permutevar8x32_ps(lo, k));
}
LANE_INLINE F loadf(const float* p) { return _mm256_load_ps(p); }
LANE_INLINE void storef(float* p, F v) { _mm256_store_ps(p, v); }
LANE_INLINE void storei(int* p, I v) { _mm256_store_si256(reinterpret_cast<I*>(p), v); }

#include "codecs/bc6h/bc6h_fast_lanes.inc"

#include "codecs/bc6h/bc6h_transpose8.inc"

}  // namespace

AVX2_FN void fit_blocks_fast_x8(const uint16_t* const h[8], const float* const x[8], const uint8_t* const valid[8],
                                OneRegionFit* const out[8]) {
  Batch B;
  Lanes& L = B.L;
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
    load_partial(L, h, x, valid);
  }
  fit_lanes(B, out);
}

}  // namespace ahd::bc6h

#else

namespace ahd::bc6h {
void fit_blocks_fast_x8(const uint16_t* const*, const float* const*, const uint8_t* const*, OneRegionFit* const*) {}
}  // namespace ahd::bc6h

#endif

// The one-region fit of `fast` (and `default`'s incumbent), sixteen blocks at a time: the fit of
// bc6h_fast_lanes.inc with one block per AVX-512 lane (mask registers for the lanes' branches,
// one permute for each 16-entry table), the same operations as the AVX2 and one-block paths in
// the same order, so the same fits, error included (tested with each path forced).
//
// Built for plain x86-64 as bc6h_fast_avx2.cpp is: only the functions here carry the AVX-512
// target attribute, and bc6h_fast.cpp calls them only when the CPU and the OS support AVX-512
// F/VL/BW/DQ (cpu_has_avx512).
#include "codecs/bc6h_fast.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
// GCC 12's AVX-512 intrinsics start their unmasked forms from _mm512_undefined_*(), which its
// -Wuninitialized reports once per inlined use (a known false positive of the header).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
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
LANE_INLINE I mulli(I a, I b) { return _mm512_mullo_epi32(a, b); }
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
LANE_INLINE F loadf(const float* p) { return _mm512_load_ps(p); }
LANE_INLINE void storef(float* p, F v) { _mm512_store_ps(p, v); }
LANE_INLINE void storei(int* p, I v) { _mm512_store_si512(p, v); }

#include "codecs/bc6h_fast_lanes.inc"

// Transposes an 8×8 matrix of floats held as eight rows (as bc6h_fast_avx2.cpp does).
LANE_INLINE void transpose8(__m256 r[8]) {
  const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
  const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
  const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
  const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
  const __m256 u0 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)), u1 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
  const __m256 u2 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)), u3 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  const __m256 u4 = _mm256_shuffle_ps(t4, t6, _MM_SHUFFLE(1, 0, 1, 0)), u5 = _mm256_shuffle_ps(t4, t6, _MM_SHUFFLE(3, 2, 3, 2));
  const __m256 u6 = _mm256_shuffle_ps(t5, t7, _MM_SHUFFLE(1, 0, 1, 0)), u7 = _mm256_shuffle_ps(t5, t7, _MM_SHUFFLE(3, 2, 3, 2));
  r[0] = _mm256_permute2f128_ps(u0, u4, 0x20), r[1] = _mm256_permute2f128_ps(u1, u5, 0x20);
  r[2] = _mm256_permute2f128_ps(u2, u6, 0x20), r[3] = _mm256_permute2f128_ps(u3, u7, 0x20);
  r[4] = _mm256_permute2f128_ps(u0, u4, 0x31), r[5] = _mm256_permute2f128_ps(u1, u5, 0x31);
  r[6] = _mm256_permute2f128_ps(u2, u6, 0x31), r[7] = _mm256_permute2f128_ps(u3, u7, 0x31);
}

}  // namespace

AVX512_FN void fit_blocks_fast_x16(const uint16_t* const h[16], const float* const x[16],
                                   const uint8_t* const valid[16], OneRegionFit* const out[16]) {
  Lanes L;
  bool all_valid = true;
  for (int l = 0; l < 16; ++l) {
    uint64_t v[2];
    std::memcpy(v, valid[l], 16);
    all_valid &= (v[0] & v[1]) == 0x0101010101010101ull;
  }
  if (all_valid) {
    // Every texel real (inner blocks): each half of the lanes transposed by 8×8 blocks of
    // columns as in the AVX2 path, the two halves joined into one register.
#pragma GCC unroll 6
    for (int j = 0; j < 48; j += 8) {
      __m256 hv[2][8], xv[2][8];
      for (int half = 0; half < 2; ++half) {
        for (int l = 0; l < 8; ++l) {
          const int b = half * 8 + l;
          hv[half][l] = _mm256_cvtepi32_ps(_mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(h[b] + j))));
          xv[half][l] = _mm256_loadu_ps(x[b] + j);
        }
        transpose8(hv[half]);
        transpose8(xv[half]);
      }
#pragma GCC unroll 8
      for (int i = 0; i < 8; ++i) {
        L.H[(j + i) % 3][(j + i) / 3] = _mm512_insertf32x8(_mm512_castps256_ps512(hv[0][i]), hv[1][i], 1);
        L.W[(j + i) % 3][(j + i) / 3] = _mm512_insertf32x8(_mm512_castps256_ps512(xv[0][i]), xv[1][i], 1);
      }
    }
    for (int t = 0; t < 16; ++t) L.vmask[t] = f32(1.0f);
  } else {
    load_partial(L, h, x, valid);
  }
  fit_lanes(L, out);
}

bool cpu_has_avx512() {
  static const bool has = [] {
    if (!cpu_has_avx2()) return false;  // also checks OSXSAVE and CPUID leaf 7
    unsigned lo = 0, hi = 0;
    __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    if ((lo & 0xE6u) != 0xE6u) return false;  // XMM, YMM, opmask and both ZMM states enabled by the OS
    unsigned a = 0, b = 0, c = 0, d = 0;
    __cpuid_count(7, 0, a, b, c, d);
    const unsigned need = (1u << 16) | (1u << 17) | (1u << 30) | (1u << 31);  // F, DQ, BW, VL
    return (b & need) == need;
  }();
  return has;
}

}  // namespace ahd::bc6h

#else

namespace ahd::bc6h {
void fit_blocks_fast_x16(const uint16_t* const*, const float* const*, const uint8_t* const*, OneRegionFit* const*) {}
bool cpu_has_avx512() { return false; }
}  // namespace ahd::bc6h

#endif

#include "codecs/bc4.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/cpu.h"
#include "core/parallel.h"

#ifdef __SSE2__
// GCC 12's AVX-512 intrinsics start their unmasked forms from _mm512_undefined_*(), which its
// -Wuninitialized reports once per inlined use (a known false positive of the header).
#pragma GCC diagnostic ignored "-Wuninitialized"
#ifndef __clang__  // clang has no such group (and warns on an unknown one)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <emmintrin.h>
#include <immintrin.h>
#endif

namespace ahd {
namespace {

#ifdef __SSE2__
// The index step on wider lanes: the 16 texels in one AVX-512 register or two AVX2 ones (the
// SSE2 loop below needs four). Each lane does what the scalar loop does — |v − p|, a strict
// compare, a select — so the distances and indices are bit for bit the same; the caller sums the
// error in texel order (outside these functions, so no FMA can fuse it). Issue 28: `assign` was
// 18 % of an L2 2048² conversion's samples with the SSE2 loop. The search now evaluates its pairs
// with the error steps further down (one lane per pair); this step gives the winner's indices
// and the errors of effort 0's one or two pairs.
__attribute__((target("avx512f"))) void nearest_avx512(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  const __m512 vi = _mm512_loadu_ps(v);
  __m512 d = _mm512_abs_ps(_mm512_sub_ps(vi, _mm512_set1_ps(pal[0])));
  __m512i kb = _mm512_setzero_si512();
  for (int k = 1; k < 8; ++k) {
    const __m512 dk = _mm512_abs_ps(_mm512_sub_ps(vi, _mm512_set1_ps(pal[k])));
    const __mmask16 closer = _mm512_cmp_ps_mask(dk, d, _CMP_LT_OQ);
    d = _mm512_mask_mov_ps(d, closer, dk);
    kb = _mm512_mask_mov_epi32(kb, closer, _mm512_set1_epi32(k));
  }
  _mm512_storeu_ps(bd, d);
  _mm512_storeu_si512(bi, kb);
}

__attribute__((target("avx2"))) void nearest_avx2(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 v0 = _mm256_loadu_ps(v), v1 = _mm256_loadu_ps(v + 8);
  const __m256 p0 = _mm256_set1_ps(pal[0]);
  __m256 d0 = _mm256_andnot_ps(sign, _mm256_sub_ps(v0, p0)), d1 = _mm256_andnot_ps(sign, _mm256_sub_ps(v1, p0));
  __m256 k0 = _mm256_setzero_ps(), k1 = _mm256_setzero_ps();  // indices as int bits in float lanes
  for (int k = 1; k < 8; ++k) {
    const __m256 pk = _mm256_set1_ps(pal[k]);
    const __m256 kk = _mm256_castsi256_ps(_mm256_set1_epi32(k));
    const __m256 e0 = _mm256_andnot_ps(sign, _mm256_sub_ps(v0, pk)), e1 = _mm256_andnot_ps(sign, _mm256_sub_ps(v1, pk));
    const __m256 c0 = _mm256_cmp_ps(e0, d0, _CMP_LT_OQ), c1 = _mm256_cmp_ps(e1, d1, _CMP_LT_OQ);
    d0 = _mm256_blendv_ps(d0, e0, c0), d1 = _mm256_blendv_ps(d1, e1, c1);
    k0 = _mm256_blendv_ps(k0, kk, c0), k1 = _mm256_blendv_ps(k1, kk, c1);
  }
  _mm256_storeu_ps(bd, d0);
  _mm256_storeu_ps(bd + 8, d1);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(bi), _mm256_castps_si256(k0));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(bi + 8), _mm256_castps_si256(k1));
}
#endif

uint64_t read_indices(const uint8_t* b) {
  uint64_t v = 0;
  for (int i = 0; i < 6; ++i) v |= uint64_t(b[2 + i]) << (8 * i);
  return v;
}

#ifdef __SSE2__
// Four texels per SSE2 register (g++ 12 left the plain loops scalar: issue 28, perf of an L2
// 2048² conversion put the index step at 25 % of its samples).
void nearest_sse2(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  const __m128 sign = _mm_set1_ps(-0.0f);
  __m128 d[4], vi[4];
  __m128i k_best[4];
  const __m128 p0 = _mm_set1_ps(pal[0]);
  for (int q = 0; q < 4; ++q) {
    vi[q] = _mm_loadu_ps(v + 4 * q);
    d[q] = _mm_andnot_ps(sign, _mm_sub_ps(vi[q], p0));
    k_best[q] = _mm_setzero_si128();
  }
  for (int k = 1; k < 8; ++k) {
    const __m128 pk = _mm_set1_ps(pal[k]);
    const __m128i kk = _mm_set1_epi32(k);
    for (int q = 0; q < 4; ++q) {
      const __m128 dk = _mm_andnot_ps(sign, _mm_sub_ps(vi[q], pk));
      const __m128 closer = _mm_cmplt_ps(dk, d[q]);
      d[q] = _mm_or_ps(_mm_and_ps(closer, dk), _mm_andnot_ps(closer, d[q]));
      const __m128i c = _mm_castps_si128(closer);
      k_best[q] = _mm_or_si128(_mm_and_si128(c, kk), _mm_andnot_si128(c, k_best[q]));
    }
  }
  for (int q = 0; q < 4; ++q) {
    _mm_storeu_ps(bd + 4 * q, d[q]);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bi + 4 * q), k_best[q]);
  }
}
#endif

// The plain loops, which every path above matches lane for lane.
void nearest_scalar(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  for (int i = 0; i < 16; ++i) bd[i] = std::fabs(v[i] - pal[0]), bi[i] = 0;
  for (int k = 1; k < 8; ++k)
    for (int i = 0; i < 16; ++i) {
      const float d = std::fabs(v[i] - pal[k]);
      const bool closer = d < bd[i];
      bd[i] = closer ? d : bd[i];
      bi[i] = closer ? k : bi[i];
    }
}

using NearestFn = void (*)(const float*, const float*, float*, int*);

// The widest index step this CPU has (asked once per block: the tests switch paths between calls).
NearestFn nearest_for_cpu() {
#ifdef __SSE2__
  if (cpu::has(cpu::kAvx512)) return nearest_avx512;
  if (cpu::has(cpu::kAvx2)) return nearest_avx2;
  if (cpu::has(cpu::kSse2)) return nearest_sse2;  // off only when the tests force the plain loops
#endif
  return nearest_scalar;
}

// The endpoint pairs a block's search has already proposed: the searches below revisit many pairs
// (neighbourhoods overlap), and a pair seen before can never win again (ties keep the first), so
// each is evaluated once. Only a saving: a repeat would have the same error and lose.
class TriedPairs {
 public:
  // Marks (r0, r1); true if it was not marked. Without branches (which pairs repeat is
  // data-dependent), and with neighbouring pairs in different words: the searches propose runs
  // of neighbours, and a run in one word would wait for each store before the next load. The
  // low 10 bits of key = r0·256 + r1 pick the word (r1 and r0's low 2 bits), the rest the bit.
  bool mark(int r0, int r1) {
    const unsigned key = unsigned(r0) << 8 | unsigned(r1);
    const uint64_t word = bits_[key & 1023], bit = uint64_t(1) << (key >> 10);
    bits_[key & 1023] = word | bit;
    return (word & bit) == 0;
  }
  // Unmarks every pair in the word of (r0, r1) (the encoder passes every pair it marked).
  void clear_word(int r0, int r1) { bits_[(unsigned(r0) << 8 | unsigned(r1)) & 1023] = 0; }

 private:
  uint64_t bits_[1024] = {};
};

void write_block(uint8_t r0, uint8_t r1, const uint8_t idx[16], uint8_t out[8]) {
  out[0] = r0;
  out[1] = r1;
  uint64_t bits = 0;
  for (int i = 0; i < 16; ++i) bits |= uint64_t(idx[i] & 7) << (3 * i);
  for (int i = 0; i < 6; ++i) out[2 + i] = uint8_t(bits >> (8 * i));
}


// n / (steps·255) rounded to float, for every numerator an interpolated entry can have
// (n = (steps+1−k)·r0 + (k−1)·r1 ≤ steps·255): the encoder's search asks for palettes millions of
// times, and a table lookup gives the very value of the division. Both tables in one array, so a
// SIMD gather reads either mode's entries from one base: by7 at 0, by5 at kBy5.
constexpr int kBy5 = 7 * 255 + 1;
struct PaletteTables {
  float v[kBy5 + 5 * 255 + 1];
  PaletteTables() {
    for (int n = 0; n <= 7 * 255; ++n) v[n] = float(n / (7 * 255.0));
    for (int n = 0; n <= 5 * 255; ++n) v[kBy5 + n] = float(n / (5 * 255.0));
  }
};

const PaletteTables& palette_tables() {
  static const PaletteTables tables;
  return tables;
}

// bc4_palette with the tables passed in (the encoder fetches them once per block).
inline void palette_from(const PaletteTables& t, int r0, int r1, float pal[8]) {
  pal[0] = float(r0) / 255.0f;
  pal[1] = float(r1) / 255.0f;
  if (r0 > r1) {
    for (int k = 2; k < 8; ++k) pal[k] = t.v[(8 - k) * r0 + (k - 1) * r1];
  } else {
    for (int k = 2; k < 6; ++k) pal[k] = t.v[kBy5 + (6 - k) * r0 + (k - 1) * r1];
    pal[6] = 0.0f;
    pal[7] = 1.0f;
  }
}

// The endpoint pairs one step of the search evaluates, in the order it tries them, and their
// errors. The pairs of a step do not depend on each other's errors, so their errors are computed
// in one batch (one SIMD lane per pair) and then scanned in order, as if tried one by one.
// Capacity: every pair one block evaluates — the fixed lists hold at most 81 + 81 + 28·9 + 15·9 =
// 549 pairs (effort ≥ 2), the ≤ 6 refinement rounds 9 each — plus the padding of a last SIMD group.
struct Candidates {
  static constexpr int kCapacity = 608;
  alignas(64) int32_t r0[kCapacity + 16];
  alignas(64) int32_t r1[kCapacity + 16];
  alignas(64) float err[kCapacity + 16];
};

// The per-pair errors: err[j] = Σ_i min_k |v_i − pal_k(r0[j], r1[j])|², summed in texel order —
// bit for bit the error the one-pair search computed (`closer = d < bd` keeps the smaller value,
// which is what min gives: d and bd are never NaN) — or, for a pair that cannot beat `bound`, a
// partial sum ≥ bound: every 4 texels, a group of lanes none of which is below `bound` stops (the
// sum never decreases: the terms are ≥ 0 and rounding is monotonic). Either way an error below
// `bound` is exact, and which pair is the first of the smallest below `bound` does not change.
// r0/r1 hold n pairs and are readable (valid pairs) up to n rounded up to 16; err is written up
// to there. Returns the smallest value written (≥ 0, never NaN: any order of min gives it).
using ErrorsFn = float (*)(const float v[16], const PaletteTables& t, const int32_t* r0, const int32_t* r1, int n,
                          float bound, float* err);

// The plain loops, which every SIMD path matches lane for lane.
float errors_scalar(const float v[16], const PaletteTables& t, const int32_t* r0, const int32_t* r1, int n, float bound,
                    float* err) {
  float m = INFINITY;
  for (int j = 0; j < n; ++j) {
    float pal[8];
    palette_from(t, r0[j], r1[j], pal);
    float e = 0;
    for (int i = 0; i < 16; ++i) {
      float bd = std::fabs(v[i] - pal[0]);
      for (int k = 1; k < 8; ++k) {
        const float d = std::fabs(v[i] - pal[k]);
        bd = d < bd ? d : bd;
      }
      e += bd * bd;
      if ((i & 3) == 3 && i < 15 && !(e < bound)) break;
    }
    err[j] = e;
    m = e < m ? e : m;
  }
  return m;
}

#ifdef __SSE2__
// Four pairs per register; the palettes built in scalar, transposed (SSE2 has no gather).
float errors_sse2(const float v[16], const PaletteTables& t, const int32_t* r0, const int32_t* r1, int n, float bound,
                  float* err) {
  const __m128 sign = _mm_set1_ps(-0.0f), bnd = _mm_set1_ps(bound);
  __m128 m = _mm_set1_ps(INFINITY);
  for (int j = 0; j < n; j += 4) {
    float pal[4][8];
    for (int l = 0; l < 4; ++l) palette_from(t, r0[j + l], r1[j + l], pal[l]);
    __m128 p[8];  // lanes from scalars (four scalar stores read back as one vector would stall)
    for (int k = 0; k < 8; ++k) p[k] = _mm_set_ps(pal[3][k], pal[2][k], pal[1][k], pal[0][k]);
    __m128 e = _mm_setzero_ps();
    for (int i = 0; i < 16; ++i) {
      const __m128 vi = _mm_set1_ps(v[i]);
      __m128 bd = _mm_andnot_ps(sign, _mm_sub_ps(vi, p[0]));
      for (int k = 1; k < 8; ++k) bd = _mm_min_ps(_mm_andnot_ps(sign, _mm_sub_ps(vi, p[k])), bd);  // d < bd ? d : bd
      e = _mm_add_ps(e, _mm_mul_ps(bd, bd));
      if ((i & 3) == 3 && i < 15 && _mm_movemask_ps(_mm_cmplt_ps(e, bnd)) == 0) break;
    }
    _mm_storeu_ps(err + j, e);
    m = _mm_min_ps(e, m);
  }
  m = _mm_min_ps(m, _mm_movehl_ps(m, m));
  m = _mm_min_ps(m, _mm_shuffle_ps(m, m, 1));
  return _mm_cvtss_f32(m);
}

// Eight pairs per register; palettes gathered from the tables (both modes, then a blend).
__attribute__((target("avx2"))) float errors_avx2(const float v[16], const PaletteTables& t, const int32_t* r0,
                                                 const int32_t* r1, int n, float bound, float* err) {
  const __m256 sign = _mm256_set1_ps(-0.0f), bnd = _mm256_set1_ps(bound);
  const __m256 inv = _mm256_set1_ps(255.0f);
  __m256 m = _mm256_set1_ps(INFINITY);
  for (int j = 0; j < n; j += 8) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(r0 + j));
    const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(r1 + j));
    const __m256 eight = _mm256_castsi256_ps(_mm256_cmpgt_epi32(a, b));
    __m256 p[8];
    p[0] = _mm256_div_ps(_mm256_cvtepi32_ps(a), inv);
    p[1] = _mm256_div_ps(_mm256_cvtepi32_ps(b), inv);
    for (int k = 2; k < 8; ++k) {
      const __m256i n8 = _mm256_add_epi32(_mm256_mullo_epi32(a, _mm256_set1_epi32(8 - k)),
                                          _mm256_mullo_epi32(b, _mm256_set1_epi32(k - 1)));
      if (k < 6) {
        const __m256i n6 = _mm256_add_epi32(_mm256_set1_epi32(kBy5),
                                            _mm256_add_epi32(_mm256_mullo_epi32(a, _mm256_set1_epi32(6 - k)),
                                                             _mm256_mullo_epi32(b, _mm256_set1_epi32(k - 1))));
        const __m256i idx = _mm256_castps_si256(
            _mm256_blendv_ps(_mm256_castsi256_ps(n6), _mm256_castsi256_ps(n8), eight));
        p[k] = _mm256_i32gather_ps(t.v, idx, 4);
      } else {
        p[k] = _mm256_blendv_ps(_mm256_set1_ps(k == 6 ? 0.0f : 1.0f), _mm256_i32gather_ps(t.v, n8, 4), eight);
      }
    }
    __m256 e = _mm256_setzero_ps();
    for (int i = 0; i < 16; ++i) {
      const __m256 vi = _mm256_set1_ps(v[i]);
      __m256 bd = _mm256_andnot_ps(sign, _mm256_sub_ps(vi, p[0]));
      for (int k = 1; k < 8; ++k) bd = _mm256_min_ps(_mm256_andnot_ps(sign, _mm256_sub_ps(vi, p[k])), bd);
      e = _mm256_add_ps(e, _mm256_mul_ps(bd, bd));
      if ((i & 3) == 3 && i < 15 && _mm256_movemask_ps(_mm256_cmp_ps(e, bnd, _CMP_LT_OQ)) == 0) break;
    }
    _mm256_storeu_ps(err + j, e);
    m = _mm256_min_ps(e, m);
  }
  __m128 h = _mm_min_ps(_mm256_castps256_ps128(m), _mm256_extractf128_ps(m, 1));
  h = _mm_min_ps(h, _mm_movehl_ps(h, h));
  h = _mm_min_ps(h, _mm_shuffle_ps(h, h, 1));
  return _mm_cvtss_f32(h);
}

// Sixteen pairs per register, as errors_avx2.
__attribute__((target("avx512f"))) float errors_avx512(const float v[16], const PaletteTables& t, const int32_t* r0,
                                                      const int32_t* r1, int n, float bound, float* err) {
  const __m512 inv = _mm512_set1_ps(255.0f), bnd = _mm512_set1_ps(bound);
  __m512 m = _mm512_set1_ps(INFINITY);
  for (int j = 0; j < n; j += 16) {
    const __m512i a = _mm512_loadu_si512(r0 + j);
    const __m512i b = _mm512_loadu_si512(r1 + j);
    const __mmask16 eight = _mm512_cmpgt_epi32_mask(a, b);
    __m512 p[8];
    p[0] = _mm512_div_ps(_mm512_cvtepi32_ps(a), inv);
    p[1] = _mm512_div_ps(_mm512_cvtepi32_ps(b), inv);
    for (int k = 2; k < 8; ++k) {
      const __m512i n8 = _mm512_add_epi32(_mm512_mullo_epi32(a, _mm512_set1_epi32(8 - k)),
                                          _mm512_mullo_epi32(b, _mm512_set1_epi32(k - 1)));
      __m512i idx = n8;
      if (k < 6) {
        const __m512i n6 = _mm512_add_epi32(_mm512_set1_epi32(kBy5),
                                            _mm512_add_epi32(_mm512_mullo_epi32(a, _mm512_set1_epi32(6 - k)),
                                                             _mm512_mullo_epi32(b, _mm512_set1_epi32(k - 1))));
        idx = _mm512_mask_mov_epi32(n6, eight, n8);
        p[k] = _mm512_i32gather_ps(idx, t.v, 4);
      } else {
        p[k] = _mm512_mask_i32gather_ps(_mm512_set1_ps(k == 6 ? 0.0f : 1.0f), eight, idx, t.v, 4);
      }
    }
    __m512 e = _mm512_setzero_ps();
    for (int i = 0; i < 16; ++i) {
      const __m512 vi = _mm512_set1_ps(v[i]);
      __m512 bd = _mm512_abs_ps(_mm512_sub_ps(vi, p[0]));
      for (int k = 1; k < 8; ++k) bd = _mm512_min_ps(_mm512_abs_ps(_mm512_sub_ps(vi, p[k])), bd);
      e = _mm512_add_ps(e, _mm512_mul_ps(bd, bd));
      if ((i & 3) == 3 && i < 15 && _mm512_cmp_ps_mask(e, bnd, _CMP_LT_OQ) == 0) break;
    }
    _mm512_storeu_ps(err + j, e);
    m = _mm512_min_ps(e, m);
  }
  return _mm512_reduce_min_ps(m);
}
#endif

// The error steps this CPU has (asked once per block, as nearest_for_cpu): the widest, and
// narrower ones for small batches (effort 0 proposes one or two pairs) — the same errors with
// fewer idle lanes.
struct ErrorPaths {
  ErrorsFn upto4, upto8, wide;
  ErrorsFn for_batch(int n) const { return n <= 4 ? upto4 : n <= 8 ? upto8 : wide; }
};

ErrorPaths errors_for_cpu() {
#ifdef __SSE2__
  const bool avx2 = cpu::has(cpu::kAvx2);
  if (cpu::has(cpu::kAvx512)) return {errors_sse2, avx2 ? errors_avx2 : errors_sse2, errors_avx512};
  if (avx2) return {errors_sse2, errors_avx2, errors_avx2};
  if (cpu::has(cpu::kSse2)) return {errors_sse2, errors_sse2, errors_sse2};
#endif
  return {errors_scalar, errors_scalar, errors_scalar};
}

// std::lround for |x| < 2^31 (halves away from zero) without the libm call, which the position
// search below makes ~90 times a block: x − trunc(x) is exact, so the comparisons decide as
// lround does.
inline int round_half_away(float x) {
  const int t = int(x);
  const float frac = x - float(t);
  return t + int(frac >= 0.5f) - int(frac <= -0.5f);
}

// The pairs of palette positions 0 ≤ ta < tb ≤ steps in the order of the loops over ta, then tb;
// as floats (the search's arithmetic converts them).
struct PositionPairs {
  int n = 0;
  float ta[28] = {}, dt[28] = {};
  constexpr explicit PositionPairs(int steps) {
    for (int a = 0; a < steps; ++a)
      for (int b = a + 1; b <= steps; ++b) ta[n] = float(a), dt[n] = float(b - a), ++n;
  }
};
constexpr PositionPairs kPositions7(7), kPositions5(5);

// The least-squares refinement's terms per index k, f = the weight of r1 in entry k: (1−f)²,
// (1−f)·f, f², 1−f and f, computed as the refinement did per texel. The 6-value mode's exact 0 and
// 1 (k ≥ 6) do not depend on the endpoints: all zero, and adding +0 to these sums (never
// negative: x = v·255 ≥ 0) leaves them as skipping the texel did.
struct RefineWeights {
  double w00[8], w01[8], w11[8], g0[8], g1[8];
  explicit RefineWeights(bool eight) {
    for (int k = 0; k < 8; ++k) {
      const double f = k == 0 ? 0.0 : k == 1 ? 1.0 : (k - 1) / (eight ? 7.0 : 5.0);
      const bool skip = !eight && k >= 6;
      w00[k] = skip ? 0.0 : (1 - f) * (1 - f), w01[k] = skip ? 0.0 : (1 - f) * f, w11[k] = skip ? 0.0 : f * f;
      g0[k] = skip ? 0.0 : 1 - f, g1[k] = skip ? 0.0 : f;
    }
  }
};

const RefineWeights& refine_weights(bool eight) {
  static const RefineWeights by7(true), by5(false);
  return eight ? by7 : by5;
}

}  // namespace

void bc4_palette(uint8_t r0, uint8_t r1, float pal[8]) {
  palette_from(palette_tables(), r0, r1, pal);
}

void bc4_decode_block(const uint8_t block[8], float out[16]) {
  float pal[8];
  bc4_palette(block[0], block[1], pal);
  const uint64_t bits = read_indices(block);
  for (int i = 0; i < 16; ++i) out[i] = pal[(bits >> (3 * i)) & 7];
}

void bc4_decode_block_unorm8(const uint8_t block[8], uint8_t out[16]) {
  const int r0 = block[0], r1 = block[1];
  const bool eight = r0 > r1;
  const uint32_t step = eight ? 255 * 64 / 7 : 255 * 64 / 5;
  uint8_t pal[8] = {uint8_t(r0), uint8_t(r1), 0, 0, 0, 0, 0, 255};
  for (int k = 2; k < (eight ? 8 : 6); ++k) {
    const uint32_t w = (step * uint32_t(k - 1)) >> 6;             // weight in 1/256 units
    const uint32_t delta = uint32_t(r1 - r0) & 0xFFFF;            // 16-bit lane arithmetic
    const uint32_t interp = ((delta * w) & 0xFFFF) >> 8;
    pal[k] = uint8_t(r0 + interp);                                // 8-bit wrap-around add
  }
  const uint64_t bits = read_indices(block);
  for (int i = 0; i < 16; ++i) out[i] = pal[(bits >> (3 * i)) & 7];
}

void bc4_encode_block(const float texels[16], uint8_t out[8], int effort) {
  float v[16];
  float lo = 1.0f, hi = 0.0f;
  for (int i = 0; i < 16; ++i) {
    v[i] = std::clamp(std::isfinite(texels[i]) ? texels[i] : 0.0f, 0.0f, 1.0f);
    lo = std::min(lo, v[i]);
    hi = std::max(hi, v[i]);
  }
  const int qlo = int(std::floor(lo * 255.0f)), qhi = int(std::ceil(hi * 255.0f));
  if (qlo == qhi) {  // constant block: exact with r0 = r1 (6-value mode, every index 0)
    const uint8_t idx[16] = {};
    const uint8_t q = uint8_t(std::lround(v[0] * 255.0f));
    write_block(q, q, idx, out);
    return;
  }
  const int radius = effort <= 0 ? 0 : effort == 1 ? 2 : 4;
  const PaletteTables& tables = palette_tables();
  const NearestFn nearest = nearest_for_cpu();
  // 6-value mode (r0 ≤ r1) with exact 0 and 1 available: endpoints span the values strictly
  // inside (0, 1), which helps blocks that touch the ends of the range.
  float ilo = 1.0f, ihi = 0.0f;
  for (float x : v)
    if (x > 0.0f && x < 1.0f) ilo = std::min(ilo, x), ihi = std::max(ihi, x);
  const bool inner = ilo <= ihi;
  const int plo = inner ? int(std::floor(ilo * 255.0f)) : -1024, phi = inner ? int(std::ceil(ihi * 255.0f)) : -1024;
  thread_local TriedPairs tried;
  Candidates c;  // every pair the block evaluates, in order; the batch is [start, n)
  int start = 0, n = 0;
  // The range searches' pairs (two grids around the ranges) are distinct: the two modes never
  // share a pair, and each grid's pairs differ. Those in range join as they come.
  auto propose_distinct = [&](int r0, int r1) {
    if ((unsigned(r0) | unsigned(r1)) > 255) return;
    c.r0[n] = r0, c.r1[n] = r1, ++n;
  };
  // Later pairs join the batch the first time they are proposed, in range: the grids' pairs are
  // recognised by their coordinates, the others marked in `tried` (effort 0 never touches it).
  const unsigned span = unsigned(2 * radius);
  auto propose = [&](int r0, int r1) {
    if ((unsigned(r0) | unsigned(r1)) > 255) return;
    const bool grid8 = r0 > r1 && unsigned(r0 - qhi + radius) <= span && unsigned(r1 - qlo + radius) <= span;
    const bool grid6 = r0 <= r1 && unsigned(r0 - plo + radius) <= span && unsigned(r1 - phi + radius) <= span;
    if (grid8 | grid6) return;
    c.r0[n] = r0, c.r1[n] = r1;
    n += tried.mark(r0, r1);
  };
  float best = INFINITY;
  uint8_t best_idx[16], b0 = 0, b1 = 0;
  // Evaluates the batch and scans it in proposal order (strict <: the first of equal errors wins),
  // as trying the pairs one by one would; the winner's indices are computed only when it changed.
  auto try_batch = [&]() {
    const int batch = n - start;
    int32_t* const r0 = c.r0 + start;
    int32_t* const r1 = c.r1 + start;
    float* const err = c.err + start;
    start = n;
    if (batch == 0) return;
    if (batch <= 2) {
      // One or two pairs (effort 0): one texel per lane, the error summed in texel order, as the
      // lanes per pair below compute it; the indices come along.
      float pal[2][8], bd[2][16], e[2] = {0, 0};
      int bi[2][16];
      for (int j = 0; j < batch; ++j) palette_from(tables, r0[j], r1[j], pal[j]), nearest(v, pal[j], bd[j], bi[j]);
      for (int i = 0; i < 16; ++i) e[0] += bd[0][i] * bd[0][i], e[1] += bd[1 % batch][i] * bd[1 % batch][i];
      for (int j = 0; j < batch; ++j)
        if (e[j] < best) {
          best = e[j], b0 = uint8_t(r0[j]), b1 = uint8_t(r1[j]);
          for (int i = 0; i < 16; ++i) best_idx[i] = uint8_t(bi[j][i]);
        }
      return;
    }
    for (int j = batch; j < ((batch + 15) & ~15); ++j) r0[j] = r0[0], r1[j] = r1[0];  // whole SIMD groups
    const ErrorPaths errors = errors_for_cpu();
    // 16 pairs at a time, each chunk bounded by the best before it (later chunks stop early more
    // often); in each, the first of the smallest below the best is the one trying them in order
    // with `e < best` would keep.
    int win = -1;
    for (int j0 = 0; j0 < batch; j0 += 16) {
      const int len = std::min(16, batch - j0);
      const float m = errors.for_batch(len)(v, tables, r0 + j0, r1 + j0, len, best, err + j0);
      if (!(m < best)) continue;
      win = j0;
      while (err[win] != m) ++win;
      best = m;
    }
    if (win < 0) return;
    b0 = uint8_t(r0[win]), b1 = uint8_t(r1[win]);
    float pal[8], bd[16];
    int bi[16];
    palette_from(tables, b0, b1, pal);
    nearest(v, pal, bd, bi);
    for (int i = 0; i < 16; ++i) best_idx[i] = uint8_t(bi[i]);
  };
  // 8-value mode: r0 > r1, endpoints near the range (hi, lo).
  for (int a = -radius; a <= radius; ++a)
    for (int b = -radius; b <= radius; ++b)
      if (qhi + a > qlo + b) propose_distinct(qhi + a, qlo + b);
  // 6-value mode (above).
  if (inner) {
    for (int a = -radius; a <= radius; ++a)
      for (int b = -radius; b <= radius; ++b)
        if (plo + a <= phi + b) propose_distinct(plo + a, phi + b);
  }
  // Ramps and clusters often fit best with endpoints BEYOND the data range, so that the data's
  // min and max land on inner palette entries: try every pair of palette positions for them.
  const int grids = n;  // pairs not marked in `tried`
  if (effort > 0) {
    for (int mode = 0; mode < 2; ++mode) {
      const bool eight = mode == 0;
      const int steps = eight ? 7 : 5;
      const float lo8 = (eight ? lo : ilo) * 255.0f, hi8 = (eight ? hi : ihi) * 255.0f;
      if (!(hi8 > lo8)) continue;
      // For each pair of positions ta < tb (in the order of the loops ta, tb): the palette values
      // at t = 0 and t = steps, rounded (all positions at once: the loops vectorize).
      const PositionPairs& pp = eight ? kPositions7 : kPositions5;
      int bs[28], tops[28];
      for (int j = 0; j < pp.n; ++j) {
        const float d = (hi8 - lo8) * float(steps) / pp.dt[j];
        const float base = lo8 - d * pp.ta[j] / float(steps);  // palette value at t = 0
        bs[j] = round_half_away(base), tops[j] = round_half_away(base + d);
      }
      for (int j = 0; j < pp.n; ++j) {
        const int b = bs[j], top = tops[j];
        for (int da = -(effort > 1); da <= (effort > 1); ++da)
          for (int db = -(effort > 1); db <= (effort > 1); ++db) {
            // 8-value mode ascends from r1 to r0; 6-value mode from r0 to r1.
            if (eight && top + da > b + db) propose(top + da, b + db);
            if (!eight && b + db <= top + da) propose(b + db, top + da);
          }
        }
    }
  }
  // The lists above do not depend on any error: one batch.
  try_batch();
  // Least-squares refinement: with the indices fixed, the best real endpoints solve a 2×2 system
  // (each palette entry is (1−f)·r0 + f·r1); round, re-assign, repeat, and look around the result.
  // Each round's pairs depend only on the best before it: one batch per round.
  if (effort > 0) {
    for (int iter = 0; iter < 2 + 2 * effort; ++iter) {
      const bool eight = b0 > b1;
      const RefineWeights& w = refine_weights(eight);
      double s00 = 0, s01 = 0, s11 = 0, t0 = 0, t1 = 0;
      for (int i = 0; i < 16; ++i) {
        const int k = best_idx[i];
        const double x = v[i] * 255.0;
        s00 += w.w00[k], s01 += w.w01[k], s11 += w.w11[k];
        t0 += w.g0[k] * x, t1 += w.g1[k] * x;
      }
      const double det = s00 * s11 - s01 * s01;
      if (std::fabs(det) < 1e-9) break;
      const int e0 = int(std::lround((t0 * s11 - s01 * t1) / det)), e1 = int(std::lround((s00 * t1 - s01 * t0) / det));
      const uint8_t p0 = b0, p1 = b1;
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          const int r0 = std::clamp(e0 + a, 0, 255), r1 = std::clamp(e1 + b, 0, 255);
          if ((r0 > r1) == eight) propose(r0, r1);
        }
      try_batch();
      if (p0 == b0 && p1 == b1) break;
    }
  }
  for (int j = grids; j < n; ++j) tried.clear_word(c.r0[j], c.r1[j]);
  write_block(b0, b1, best_idx, out);
}

std::vector<uint8_t> bc4_encode_image(const ImageF& img, int channel, int threads, int effort) {
  const int bw = (img.width + 3) / 4, bh = (img.height + 3) / 4;
  std::vector<uint8_t> out(size_t(bw) * bh * 8);
  parallel_for(size_t(bw) * bh, threads, 64, [&](size_t b) {
    const int bx = int(b % bw), by = int(b / bw);
    float v[16];
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        const int sx = std::min(bx * 4 + x, img.width - 1), sy = std::min(by * 4 + y, img.height - 1);
        v[y * 4 + x] = img.at(sx, sy)[channel];
      }
    bc4_encode_block(v, &out[b * 8], effort);
  });
  return out;
}

void bc4_decode_image(const uint8_t* blocks, int width, int height, int stride, int offset, ImageF& out, int channel) {
  const int bw = (width + 3) / 4, bh = (height + 3) / 4;
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      float v[16];
      bc4_decode_block(blocks + (size_t(by) * bw + bx) * stride + offset, v);
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
          const int px = bx * 4 + x, py = by * 4 + y;
          if (px < width && py < height) out.at(px, py)[channel] = v[y * 4 + x];
        }
    }
}

}  // namespace ahd

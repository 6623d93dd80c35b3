// The real-time BC6H path (quality `fast`, UF16) and its half-float conversion. Internal to the
// codec: bc6h_encode_image calls it; tests call it to force each conversion path.
#pragma once
#include <cstddef>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ahd::bc6h {

// Half-float bit patterns of n finite floats, rounded to nearest even (exactly Imath::half's
// bits). Uses the CPU's F16C instructions when cpu::has(cpu::kF16c) and the portable bit-exact
// path otherwise; both give the same bits.
void floats_to_half(const float* in, uint16_t* out, int n);
// The two paths themselves (tests compare them): the portable one, and F16C
// (bc6h_half_f16c.cpp; call only when cpu::has(cpu::kF16c)).
void floats_to_half_portable(const float* in, uint16_t* out, int n);
void floats_to_half_f16c(const float* in, uint16_t* out, int n);

// On x86-64 the fast fit's palette and projection and the search's index step (bc6h_encoder.cpp)
// run four lanes at a time with SSE2 (the x86-64 baseline, so in the generic files), and `fast`
// encodes eight blocks per AVX2 batch when the CPU has AVX2, sixteen per AVX-512 batch when it has
// AVX-512. Which path runs is cpu::has's answer (core/cpu.h); tests turn the wider paths off with
// cpu::ScopedDisable and compare the bytes (every path writes the same bytes).

// The principal axis of a weighted covariance (xx yy zz xy xz yz) by four power steps from its
// diagonal, each normalised by its largest component (no square root); *len2 = |ax|² (an axis of
// ones, 3, when the covariance is zero). The fast fit and its two-region candidate share it.
inline void principal_axis(const float cov[6], float ax[3], float* len2) {
  ax[0] = cov[0], ax[1] = cov[1], ax[2] = cov[2];
  for (int it = 0; it < 4; ++it) {
    const float v0 = cov[0] * ax[0] + cov[3] * ax[1] + cov[4] * ax[2];
    const float v1 = cov[3] * ax[0] + cov[1] * ax[1] + cov[5] * ax[2];
    const float v2 = cov[4] * ax[0] + cov[5] * ax[1] + cov[2] * ax[2];
    const float m = std::max({std::fabs(v0), std::fabs(v1), std::fabs(v2)});
    if (!(m > 0)) break;
    ax[0] = v0 / m, ax[1] = v1 / m, ax[2] = v2 / m;
  }
  *len2 = ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2];
  if (!(*len2 > 0)) ax[0] = ax[1] = ax[2] = 1, *len2 = 3;
}

// One channel's endpoints (a, b) from the least-squares sums of a region (s00 = Σw(1−g)²,
// s01 = Σw(1−g)g, s11 = Σwg², t0 = Σw(1−g)h, t1 = Σwgh), kept in [0, cap]: one endpoint past the
// cap is held at it and the other solved again (the optimum on that edge of the allowed range,
// not both clamped on their own — the no-specks cap costs less: `fast` on the noisy image
// 0.04711 → 0.04687). Returns false when the system is singular.
inline bool solve_endpoints_held_cap(float s00, float s01, float s11, float t0, float t1, float cap, float* a,
                                     float* b) {
  const float det = s00 * s11 - s01 * s01;
  if (!(std::fabs(det) > 1e-6f * (s00 * s11 + 1e-30f))) return false;
  float va = (t0 * s11 - s01 * t1) / det, vb = (s00 * t1 - s01 * t0) / det;
  if (vb > cap && !(va > cap)) vb = cap, va = (t0 - s01 * cap) / s00;
  else if (va > cap && !(vb > cap)) va = cap, vb = (t1 - s01 * cap) / s11;
  *a = std::clamp(va, 0.0f, cap);
  *b = std::clamp(vb, 0.0f, cap);
  return true;
}

// A one-region fit: mode (10..13, 0-based), absolute endpoints, indices (texel 0's may have its
// top bit set: the caller mirrors), and the weighted squared error in half steps it minimised.
struct OneRegionFit {
  int mode;
  int e[2][3];
  uint8_t idx[16];
  float err;
};

// The fit encode_block_fast writes, before the anchor mirror and packing (same arguments and
// guarantees); quality `default` starts its search from it. The least-squares step holds an
// endpoint that lands past the no-specks cap at the cap and solves the other again.
void fit_one_region_fast(const uint16_t h[48], const float x[48], const uint8_t valid[16], OneRegionFit* out);

// Writes a one-region fit as a block (mirrored first when texel 0's index has its top bit set);
// the second form takes the indices as nibbles, texel t's at bits 4t.
void pack_one_region(OneRegionFit fit, uint8_t out[16]);
void pack_one_region(int mode, const int e[2][3], uint64_t idx, uint8_t out[16]);

// fit_one_region_fast for eight blocks at once, one per AVX2 lane (bc6h_fast_avx2.cpp): *out[l]
// (skipped when null) gets exactly the fit fit_one_region_fast(h[l], x[l], valid[l]) gives, its
// error bit for bit, whatever the other lanes hold. Call only when cpu::has(cpu::kAvx2).
void fit_blocks_fast_x8(const uint16_t* const h[8], const float* const x[8], const uint8_t* const valid[8],
                        OneRegionFit* const out[8]);

// fit_blocks_fast_x8 for `batches` (1..kMaxBatches) batches of sixteen blocks, one block per
// AVX-512 lane (bc6h_fast_avx512.cpp; block i: h[i], x[i], valid[i] → *out[i], skipped when
// null): the same fits as fit_one_region_fast. The second least-squares pass's index step runs
// on the lanes that need it gathered from all the batches. Call only when
// cpu::has(cpu::kAvx512). h[i] must be the half bits of x[i] (floats_to_half's):
// batches of whole blocks convert x themselves.
constexpr int kMaxBatches = 8;
void fit_blocks_fast_x16n(int batches, const uint16_t* const h[], const float* const x[], const uint8_t* const valid[],
                          OneRegionFit* const out[]);

// fit_blocks_fast_x16n with each fit written as pack_one_region writes it: block i at blocks[i]
// (16 bytes) and its fit error at *err[i], both skipped when blocks[i] is null (`fast` packs in
// the lanes instead of block by block).
void encode_blocks_fast_x16n(int batches, const uint16_t* const h[], const float* const x[], const uint8_t* const valid[],
                             uint8_t* const blocks[], float* const err[]);

// The two-region candidate of `fast` (bc6h_fast_two_region.cpp): when one_err (the one-region
// fit's error, weighted squared half steps) is above its gate, fits the best-ranked partition and
// overwrites out (the one-region block) when its error is lower; returns whether it did. Same
// no-specks bound; depends only on its arguments.
bool improve_with_two_regions(const uint16_t h[48], const float x[48], const uint8_t valid[16], float one_err,
                              uint8_t out[16]);

// Fits n UF16 blocks (block i: h + 48i, x + 48i, valid + 16i → fits[i]), each exactly as
// fit_one_region_fast fits it alone: sixteen per AVX-512 batch when cpu::has(cpu::kAvx512), else
// eight per AVX2 batch when cpu::has(cpu::kAvx2), else one block at a time; a partial batch is padded with copies of its first block.
void fit_blocks_fast(const uint16_t* h, const float* x, const uint8_t* valid, int n, OneRegionFit* fits);

// Encodes n UF16 blocks (block i → out + 16i), each exactly as encode_block_fast encodes it
// alone (the fits of fit_blocks_fast, packed).
void encode_blocks_fast(const uint16_t* h, const float* x, const uint8_t* valid, int n, uint8_t* out);

// Copies the 4×4 block of a 3-channel float image whose top-left texel is `p` (rows `stride`
// floats apart) into rgb[t*3+c] and returns true when every value lies in [0, 65504], where the
// UF16 input rule changes nothing; returns false (rgb unspecified) otherwise, and the caller
// applies the rule value by value. Four values per SSE2 compare on x86-64.
bool copy_block_in_range(const float* p, size_t stride, float rgb[48]);

// Encodes one UF16 block without search (see bc6h_fast.cpp). h: the texels' half bits
// (h[t*3+c], finite, non-negative), x: the same values as floats, valid: 1 for real texels, 0 for
// the padding of partial blocks (not fitted, not counted). No decoded value exceeds its channel's
// brightest valid input by more than one half step. Depends only on its arguments.
void encode_block_fast(const uint16_t h[48], const float x[48], const uint8_t valid[16], uint8_t out[16]);

}  // namespace ahd::bc6h

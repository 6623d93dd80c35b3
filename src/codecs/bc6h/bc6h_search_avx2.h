// The searched encoder's index step (bc6h_encoder.cpp's evaluate) with AVX2: eight palette
// entries per vector. Internal to the codec.
#pragma once
#include <cstdint>

namespace ahd::bc6h {

// For each texel t, the palette entry of its region ((mask >> t) & 1) nearest to its target
// (target[c][t], channel planes; squared distance over the three channels, the first such entry
// on ties) into idx[t]; returns the sum over texels, in texel order, of valid[t] · that distance
// (float products added in double), or 1e300 when some texel's nearest entry is at or above
// `off` (no entry inside the block's range; idx is then written up to that texel). pal[r][c][k]:
// entry k of region r, channel c, for k < n (n = 8 or 16). The same results as the SSE2 and
// scalar loops of evaluate. Call only when cpu::has(cpu::kAvx2).
double pick_indices_avx2(const float target[3][16], const float valid[16], const float pal[2][3][16], uint16_t mask,
                         int n, float off, uint8_t idx[16]);
// The partition ranking's residual (bc6h_encoder.cpp's pair_residual_sse2) for `pairs` pairs of
// partitions, two per step: m[j][k] = {region 0 of partition 2j, region 1 of 2j, region 0 of
// 2j + 1, region 1 of 2j + 1}, k over w, s[0..2], ss[0..5]; out[p] = the two residuals of
// partition p added. The same operations in the same order per lane, so the same doubles. Call
// only when cpu::has(cpu::kAvx2).
void pair_residuals_avx2(const double m[][10][4], int pairs, double* out);

// The partition ranking's moments (bc6h_encoder.cpp's try_two_regions) for all 32 partitions, in
// pair_residuals_avx2's layout: pt[t] = texel t's moments (w, s[0..2], ss[0..5], two padding
// zeros), all = their sum. Region 1 of partition p is the sum of its four rows' subsets (each
// row's subset sums built as the encoder builds them: 0 + the texels in ascending order), added
// in row order; region 0 is all minus region 1. The same additions per component, so the same
// doubles as the scalar loops. Call only when cpu::has(cpu::kAvx2).
void partition_moments_avx2(const double pt[16][12], const double all[10], const uint16_t partitions[32],
                            double m[16][10][4]);

// The weighted means and covariances of a partition's two regions (bc6h_encoder.cpp's
// axis_endpoints_pair): region r = bit t of mask; mean[r] = Σ tw·q / Σ tw (Σ tw ≤ 0 taken as 1),
// cov[r][i][j] = Σ (tw·d[i])·d[j] with d = q − mean[r], each sum in texel order. A texel adds
// +0 to the other region's sums, which changes none of them (they start at +0 and never become
// −0), so the doubles are the scalar loops'. Call only when cpu::has(cpu::kAvx2).
void region_moments_pair_avx2(const double q[16][3], const double tw[16], uint16_t mask, double mean[2][3],
                              double cov[2][3][3]);

// polish_steps' error of one channel (bc6h_encoder.cpp) with eight index groups per vector: for
// groups i < ng (arrays filled up to a multiple of eight, padding with gn = 0), region fr[i],
// weights fwa[i] / fwb[i] on the unquantised components u (u[0], u[1] region 0, u[2], u[3] region
// 1), the decoded half bits h, and the sum of gn[i]·(L[h] − gm[i])² in the four-lane order of the
// SSE2 loop (lane i mod 4, then the lanes added pairwise). *over = some group's h is above cap.
// The same float operations, so the same value. Call only when cpu::has(cpu::kAvx2).
float held_channel_error_avx2(const int u[4], int ng, const float fr[16], const float fwa[16], const float fwb[16],
                              const float gn[16], const float gm[16], int cap, const float* L, bool* over);

// held_channel_error_avx2 for two sets of components at once (err[0], over[0] for ua; err[1],
// over[1] for ub): the same values, without a branch between the two, so their latencies overlap
// (polish_steps tries a component's step down and up this way). Call only when cpu::has(cpu::kAvx2).
void held_channel_error_pair_avx2(const int ua[4], const int ub[4], int ng, const float fr[16], const float fwa[16],
                                  const float fwb[16], const float gn[16], const float gm[16], int cap, const float* L,
                                  float err[2], bool over[2]);

}  // namespace ahd::bc6h

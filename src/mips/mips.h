// Mip chains built in the SH domain, then fitted and dilated level by level.
//
// Why the SH domain: the SH coefficients (and every quantity linear in them, above all I_z, the
// irradiance along the normal) can be box-filtered exactly, while AHD is non-linear (paper 000 §2:
// the mix of two AHD lobes is not an AHD lobe). So each level is filtered as SH, then FITTED on its
// own, and I_z of level k+1 is exactly the filtered I_z of level k (to float rounding), which is
// what the GPU's filtering of the I_z plane between levels assumes.
//
// Rules (each one tested in tests/unit/mips_test.cpp):
// - Sizes: the D3D/Vulkan chain, max(1, floor(n/2)) per axis, down to 1×1; 1×N and N×1 levels
//   keep the size-1 axis (identity filter on it).
// - Filter per axis (separable, weights sum to 1, every source texel contributes in total exactly
//   n_dst/n_src, i.e. nothing is dropped for odd sizes):
//     n_src = 1      : 1 tap  {1}
//     n_src even     : 2 taps {½, ½} on texels 2i, 2i+1
//     n_src = 2m+1   : 3 taps on texels 2i, 2i+1, 2i+2 with weights (m−i, m, i+1) / (2m+1)
//                      (the exact box of width (2m+1)/m; the classic polyphase NPOT filter).
// - Coverage: a coarse texel is covered when any child with nonzero weight is covered; its SH is
//   the tap-weighted mean over the COVERED children only (weights renormalised), so gutters never
//   leak into charts. Uncovered coarse texels get zero SH (dilation after the fit gives them values).
//   Without chart ids, a coarse texel whose footprint spans two charts (gutter narrower than 2^k
//   texels at level k) mixes them: atlases reserve gutters/alignment for the levels they need.
// - World-space SH (ShImage::normals non-empty): see NormalRule.
#pragma once
#include <vector>

#include "fit/fit_image.h"
#include "mips/dilate.h"
#include "sh/sh_image.h"

namespace ahd {

// World-space SH with per-texel normals: filtering and rotating into the local frame do not
// commute on curved charts (the children have different frames).
enum class NormalRule {
  // Default. Each child is rotated into ITS OWN local frame (frame_from_normal) first, then the
  // local-frame SH is averaged. Chosen because the planes store local-frame values and the GPU
  // filters them in local-frame terms, and because it keeps I_z (and all local-frame SH) exactly
  // linear across levels: no pops between levels. Levels ≥ 1 hold local-frame SH; their normals are
  // all +z (frame_from_normal(+z) is exactly the identity) rather than empty, so every level of a
  // chain has normals iff level 0 has (the intermediate EXR stores one channel set for all levels).
  RotateThenAverage,
  // World-space SH and normals are averaged (normals renormalised; a zero mean normal falls back to
  // the first covered child's normal) and the fit rotates afterwards. World-space lighting of the
  // mean surface, but I_z of level k+1 is NOT the mean of level k's I_z on curved charts.
  AverageThenRotate,
};

// Number of levels of the full chain for a w×h image: 1 + floor(log2(max(w, h))).
int mip_level_count(int width, int height);

// Levels of a chain limited to `max_levels` (0 = the full chain). Throws ahd::Error when negative.
int chain_level_count(int width, int height, int max_levels);

// Size of level `level` along an axis of size n0: max(1, n0 >> level).
int mip_size(int n0, int level);

// The filter taps of coarse texel i when downsampling an axis of n_src texels (see the rules
// above): up to 3 (index, weight) pairs, returns the count. Exposed for tests and other filters.
struct MipTap {
  int index;
  double weight;
};
int mip_taps(int n_src, int i, MipTap taps[3]);

// The SH mip chain: element 0 is a copy of level0, then each level filtered from the previous one.
// max_levels: 0 = the full chain down to 1×1, otherwise at most that many levels (≥ 1).
// Deterministic whatever `threads` (0 = all hardware threads). Throws ahd::Error on a malformed image.
std::vector<ShImage> build_sh_mips(const ShImage& level0, int max_levels, int threads,
                                   NormalRule rule = NormalRule::RotateThenAverage);

// One SH level down (what build_sh_mips repeats).
ShImage downsample_sh(const ShImage& src, int threads, NormalRule rule = NormalRule::RotateThenAverage);

// What the pipeline's fit stage needs in one call: SH mips → fit of every level → dilation of
// every level's uncovered texels (dilate_ahd). stats/dilate_stats, when given, receive one entry
// per level. Uncovered texels of the result never depend on the input's uncovered texels.
std::vector<FittedLevel> fit_mip_chain(const ShImage& level0, const FitOptions& opt, int max_levels,
                                       int threads, std::vector<FitStats>* stats = nullptr,
                                       std::vector<DilateStats>* dilate_stats = nullptr,
                                       NormalRule rule = NormalRule::RotateThenAverage);

// One level of that chain: fit every texel of `sh` (taken over into the result), then dilate the
// uncovered ones. Throws ahd::Error on a malformed image.
FittedLevel fit_level(ShImage&& sh, const FitOptions& opt, int threads, FitStats* stats = nullptr,
                      DilateStats* dilate_stats = nullptr);

// fit_level for an L0 image (sh.coeffs == 1, plain lightmaps), whose fit is the pure ambient lobe
// everywhere: an ambient-only level (fit_image.h FittedLevel) that stores no fit at all — its
// texels' fits (fitted_texel) are bit for bit fit_level's. Throws ahd::Error on a malformed image
// or one with L1/L2 coefficients.
FittedLevel fit_ambient_level(ShImage&& sh, const FitOptions& opt, int threads, FitStats* stats = nullptr,
                              DilateStats* dilate_stats = nullptr);

// The same, taking level 0 over (moved into the result's level 0): no copy of the largest level.
std::vector<FittedLevel> fit_mip_chain(ShImage&& level0, const FitOptions& opt, int max_levels, int threads,
                                       std::vector<FitStats>* stats = nullptr,
                                       std::vector<DilateStats>* dilate_stats = nullptr,
                                       NormalRule rule = NormalRule::RotateThenAverage);

}  // namespace ahd

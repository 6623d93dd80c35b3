// Accuracy measured against the source SH: irradiance for normals spread over the upper
// hemisphere and for the surface normal, per texel, summarised over covered texels.
// Every stage (fit, quantisation, mips, end to end) reports its error through this one module.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include "sh/sh_image.h"

namespace ahd {

// An AHD lobe to evaluate at a texel: I(n) = ca + max(0, n·d) cd, d unit, local frame.
struct AhdLobe {
  double ca[3];
  double cd[3];
  double d[3];
};

struct ErrorStat {
  double mean = 0, p99 = 0, max = 0;
};

struct ErrorReport {
  size_t texels = 0;      // covered texels measured
  size_t population = 0;  // covered texels the figures stand for (> texels: a sampled estimate)
  ErrorStat rmse;         // per texel: RMS over hemisphere normals and channels, irradiance units
  ErrorStat relative;     // per texel: rmse / mean luminance irradiance over the hemisphere
  ErrorStat log2;         // per texel: RMS of log2(1+I) − log2(1+E) over normals and channels
  ErrorStat normal_rel;   // per texel: |I(z) − E(z)| (max channel) / luminance E(z): the I_z error
  size_t negative = 0;    // texels where the lobe has a negative colour
};

// The fixed hemisphere sample set: `count` directions, equal-area (Fibonacci) spiral on z ≥ 0.
std::vector<double> hemisphere_directions(int count);

// Measures lobes[i] (i over all texels; only covered ones are measured) against the SH.
ErrorReport measure_error(const ShImage& sh, const std::vector<AhdLobe>& lobes, int threads,
                          int directions = 64);

// The lobe of texel i (an index over all texels), computed on demand so no image of lobes is needed.
using LobeAt = std::function<AhdLobe(size_t texel)>;

// The same with each lobe made on demand (called once per covered texel, from worker threads):
// identical figures, without an image of 72-byte lobes beside the SH.
ErrorReport measure_error(const ShImage& sh, const LobeAt& lobe, int threads, int directions = 64);

// The figures of one texel that the reports summarise: rmse, rel (`relative`), lg (`log2`),
// nrel (`iz_relative`, along the normal) and whether the lobe has a negative colour.
struct TexelError {
  double rmse, rel, lg, nrel;
  bool negative;
};

// Texel i's figures against the SH, over `directions` directions dirs = hemisphere_directions(directions).
TexelError texel_error(const ShImage& sh, size_t i, const AhdLobe& lobe, const double* dirs, int directions);

// True when measure_error(sh, lobes, …, directions).relative.p99 would exceed `threshold` — the
// same per-texel figure and percentile — found texel by texel with an early exit, so a clearly
// directional lightmap is decided after a few hundred texels. Single-threaded, deterministic.
bool relative_p99_exceeds(const ShImage& sh, const std::vector<AhdLobe>& lobes, double threshold,
                          int directions = 64);

// --- Sampled estimates (what a conversion prints by default; the full figures above on request) ---
//
// Sample size 4096 texels per image (all covered texels when there are fewer: the estimate is
// then the full measurement, exactly). Why 4096: the per-texel relative error of real lightmaps has
// a coefficient of variation of about 0.5–1, so the standard error of the mean is 0.8–1.6 % of it
// (σ/√4096); stratification only lowers that. For the p99, the sample's 99th percentile lies at a
// true quantile of 0.99 ± √(0.99·0.01/4096) = 0.99 ± 0.0016 (one standard error), i.e. between the
// true p98.7 and p99.3 at 2σ; the value error that maps to depends on the tail's slope (measured:
// tests/unit/error_estimate_test.cpp: mean within 3 %, p99 within 10 %). The cost is 4096 × 64 directions, ≈ 10 ms: under 1 % of a
// 1024² conversion. `max` of an estimate is the sample's max (a lower bound of the true max).
constexpr int kErrorSampleSize = 4096;

// The fixed, deterministic, stratified sample of covered texels: the covered texels in raster order
// are cut into `sample` strata of (nearly) equal count and one texel is taken from each at a hashed
// offset. Every covered texel when there are at most `sample` of them. Sorted, no repeats.
std::vector<size_t> error_sample(const std::vector<uint8_t>& coverage, int sample = kErrorSampleSize);

// measure_error over error_sample(sh.coverage, sample) only: the same per-texel figures,
// summarised over the sample (texels = sample count, population = covered texels). Parallel and
// deterministic whatever `threads`.
ErrorReport estimate_error(const ShImage& sh, const LobeAt& lobe, int threads, int sample = kErrorSampleSize,
                           int directions = 64);
ErrorReport estimate_error(const ShImage& sh, const std::vector<AhdLobe>& lobes, int threads,
                           int sample = kErrorSampleSize, int directions = 64);

// relative_p99_exceeds over error_sample(sh.coverage, sample): true when the sample's relative
// p99 exceeds `threshold`, with the same early exit. Identical to relative_p99_exceeds when the
// image has at most `sample` covered texels. Single-threaded, deterministic.
bool sampled_relative_p99_exceeds(const ShImage& sh, const LobeAt& lobe, double threshold,
                                  int sample = kErrorSampleSize, int directions = 64);

// True when every coefficient above L0 of every covered texel is exactly zero (a plain lightmap,
// or SH whose L1 and L2 are exactly zero): the irradiance is then the same for every normal, so
// I_z alone decodes it exactly. Stops at the first nonzero value; no other work.
bool sh_is_constant(const ShImage& sh);

}  // namespace ahd

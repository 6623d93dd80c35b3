// Accuracy measured against the source SH: irradiance for normals spread over the upper
// hemisphere and for the surface normal, per texel, summarised over covered texels.
// Every stage (fit, quantisation, mips, end to end) reports its error through this one module.
#pragma once
#include <cstddef>
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

// True when measure_error(sh, lobes, …, directions).relative.p99 would exceed `threshold` — the
// same per-texel figure and percentile — found texel by texel with an early exit, so a clearly
// directional lightmap is decided after a few hundred texels. Single-threaded, deterministic.
bool relative_p99_exceeds(const ShImage& sh, const std::vector<AhdLobe>& lobes, double threshold,
                          int directions = 64);

}  // namespace ahd

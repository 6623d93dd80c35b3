// How close the fitted AHD planes are to the source SH over the whole hemisphere, in closed form
// (exact integrals, no direction sampling), against the unconstrained least-squares AHD at the
// linear d — the figures of issue 18 / docs/fit.md "Choosing the direction beyond the paper". Also the coherence of d
// between neighbouring texels and the error between texel centres under bilinear filtering.
#pragma once
#include <cstddef>
#include <cstdint>

#include "fit/fit_image.h"
#include "sh/sh_image.h"

namespace ahd {

struct FitQuality {
  size_t texels = 0;     // covered texels measured
  double fit_rms = 0;    // mean over texels of the planes' hemisphere RMS error (√(Σ_c∫(I−E_c)²/(3·2π)))
  double ls_rms = 0;     // the same for the unconstrained LS AHD at the linear d (after the horizon rule)
  double fit_rel = 0;     // mean over texels of fit RMS / the texel's hemisphere-mean luminance irradiance
  double ls_rel = 0;
  double texel_ratio = 0; // mean over texels of fit RMS / LS RMS (texels with LS RMS > 0)
  // Issue 18's own measure, as it states it: the RMS over `directions` sampled normals (the
  // equal-area spiral of hemisphere_directions, uniform in solid angle) and the three channels,
  // fitted planes vs the unconstrained LS AHD at the linear d. Mean over texels of the per-texel
  // ratio (texels with sampled LS RMS > 1e-6 × their mean irradiance: the LS lobe is exact on
  // pure ambient, where the ratio is 0/0), and the ratio of the mean RMS errors.
  int directions = 0;
  double sampled_texel_ratio = 0;
  double sampled_ratio = 0;
  double ratio() const { return ls_rms > 0 ? fit_rms / ls_rms : 1.0; }
  double rel_ratio() const { return ls_rel > 0 ? fit_rel / ls_rel : 1.0; }
};

// The planes of `fit` (iz, d, ratio: decoded as ahd_decode.h does) against the SH of `sh`,
// covered texels only. opt gives dz_min and the luminance weights of the linear d. `directions`
// sampled normals for the sampled figures (0: skip them).
FitQuality fit_quality(const ShImage& sh, const AhdImage& fit, const FitOptions& opt, int threads,
                       int directions = 0);

// p99 over pairs of covered horizontal and vertical neighbours of the angle between their d, in
// degrees. 0 when there are no such pairs.
double direction_p99_angle_deg(const AhdImage& fit);

// Mean hemisphere RMS error at sub-texel positions under bilinear filtering: for every 2×2 quad of
// covered texels, the planes are interpolated at (¼,¼), (½,½), (¾,¾), (½,0), (0,½) of the quad and
// decoded, and compared with the same interpolation of the SH. Returns {planes' mean, mean of the
// hemisphere-mean luminance irradiance} so that callers can report it relative.
struct FilteredError {
  size_t samples = 0;
  double rms = 0;   // mean RMS error over samples
  double mean_irradiance = 0;  // mean over samples of the SH's hemisphere-mean luminance irradiance
};
FilteredError filtered_error(const ShImage& sh, const AhdImage& fit, const FitOptions& opt);

// `n` texels (n×1, L2, tangent space) of random lighting: ambient plus 1–3 directional lights from
// anywhere on the sphere, random colours, over four decades of brightness. Deterministic in seed.
// `saturation` s mixes each light's (and the ambient's) colour as grey·(1−s) + s·independent, with
// grey one uniform draw for the three channels and independent three draws: 1 = independent
// channels (the draws of the original set, same texels), 0 = white lights of random brightness.
// `ambient`: the ambient's brightness relative to a light's (uniform draw × this).
ShImage random_lighting_set(int n, uint32_t seed, double saturation = 1.0, double ambient = 0.1);

// Issue 18's sets, calibrated so that the linear fit reproduces the "today" column
// (docs/fit.md "Choosing the direction beyond the paper"; `ahdpack report fit`): random lighting with light colours 90 % saturated
// and a dimmer ambient (linear: RGB 1.309, luminance 1.568; issue 1.31 / 1.56), and a "smooth
// scene": the analytic scene (sample/analytic_baker.h) as L1 input, without the point light (no hard
// shadow) and with the sky ×4 (linear: 1.03 / 1.05; issue 1.03 / 1.06).
constexpr double kCalibratedSaturation = 0.9;
constexpr double kCalibratedAmbient = 0.04;
constexpr double kSmoothPointScale = 0.0;
constexpr double kSmoothSkyScale = 4.0;
constexpr double kSmoothCeilingScale = 1.0;
constexpr double kSmoothBounceScale = 1.0;
constexpr int kSmoothCoeffs = 4;

}  // namespace ahd

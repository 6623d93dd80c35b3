// The direction and ratio planes at a fraction of the lightmap's resolution (issue 43: profiles
// below 2.5 B/texel, profile field "dir_ratio_scale"). I_z stays full resolution and exact; the
// decoder samples the low-res planes bilinearly at the full-res texel centres with the same
// normalised UV (clamp to edge), as a GPU does. Whatever low-res d and ratio are stored, every
// full-res texel still decodes to non-negative colours with I(z) = I_z (the horizon rule holds
// after filtering, ratio ∈ [0,1] is convex): only the error depends on this fit.
#pragma once
#include <cstdint>
#include <vector>

#include "fit/ahd_fit.h"
#include "sh/sh_image.h"

namespace ahd {

// Where texel x of a `full`-texel row samples a `low`-texel row: at u = (x + 0.5) / full, low-res
// coordinate t = u·low − 0.5, value = (1 − w1)·v[x0] + w1·v[x1] with x0 = ⌊t⌋, both taps clamped
// to [0, low − 1] (clamp to edge). low ≥ 1, full ≥ 1.
struct BilinearTap {
  int x0 = 0, x1 = 0;
  double w1 = 0;
};
BilinearTap bilinear_tap(int full, int low, int x);

// A lw×lh image of `channels` floats a texel sampled bilinearly (bilinear_tap in x and y) at every
// texel centre of a w×h image: dst holds w·h·channels floats.
void bilinear_upsample(const float* src, int lw, int lh, int channels, int w, int h, float* dst);

// The low-res texel whose box holds full-res texel x: ⌊(x + 0.5)·low / full⌋ (the nearest one).
inline int box_owner(int full, int low, int x) {
  return int((int64_t(2 * x + 1) * int64_t(low)) / (2 * int64_t(full)));
}

// The directions of a lw×lh plane over the w×h image `sh`: a low-res texel whose box holds covered
// texels takes the direction the fit of `opt` chooses on the mean of their local polynomials
// (coverage 1); the others d = z (coverage 0, for the caller to dilate). d: 3 floats a texel.
struct LowResDirections {
  int width = 0, height = 0;
  std::vector<float> d;
  std::vector<uint8_t> coverage;
};
LowResDirections lowres_directions(const ShImage& sh, int lw, int lh, const FitOptions& opt, int threads);

// Each full-res texel's hemisphere error as a quadratic in the ratio r it decodes with, given its
// own decoded I_z and direction: err(r) = a r² − 2 n r + const, per ratio channel (1 in the
// luminance form: summed over the colours; 3 in the RGB form). Uncovered texels: a = n = 0.
struct RatioQuadratics {
  int width = 0, height = 0, channels = 1;
  std::vector<double> a, n;  // width·height·channels
};
// iz, d: w·h·3 floats, what the decoder reads at each texel (d need not be unit length: it is
// normalised and put above the horizon as the decoder does).
RatioQuadratics ratio_quadratics(const ShImage& sh, const float* iz, const float* d, const FitOptions& opt,
                                 int threads);

// The least-squares ratio of each low-res texel over the full-res texels of its box (n/a summed,
// clamped to [0,1]; 1 where the box has no weight): lw·lh·channels floats.
std::vector<float> lowres_box_ratio(const RatioQuadratics& q, int lw, int lh);

// Projected Gauss–Seidel sweeps on the ratio plane `ratio` (lw·lh·channels, in/out): each low-res
// texel in turn takes the value in [0,1] minimising the summed error of every full-res texel whose
// bilinear taps reach it. Texels of one parity class in x and y share no full-res texel, so each
// class is updated in parallel with the same bytes at any thread count. Never raises the error.
void lowres_ratio_sweeps(const RatioQuadratics& q, int lw, int lh, std::vector<float>& ratio, int sweeps, int threads);

// Pattern-search sweeps on the low-res direction plane `uv` (hemi-octahedral in [0,1]², lw·lh·2,
// in/out) with its ratio plane `ratio` (lw·lh·channels, in/out): each low-res texel in turn takes,
// among its current uv, its 8 neighbours' and its uv moved by ±step along u and v (step 1/32, halved
// each sweep), the one whose bilinearly sampled directions give the lowest summed hemisphere error
// of the full-res texels its taps reach — each with its own I_z (iz: w·h·3) and with the texel's
// ratio re-solved for that candidate. Parity classes as lowres_ratio_sweeps: thread-count
// independent. Texels whose taps reach no covered texel keep their values.
void lowres_direction_sweeps(const ShImage& sh, const float* iz, int lw, int lh, std::vector<float>& uv,
                             std::vector<float>& ratio, const FitOptions& opt, int sweeps, int threads);

// The summed error Σ (a r² − 2 n r) over the full-res texels of the bilinearly sampled plane (for
// tests and measurement).
double lowres_ratio_objective(const RatioQuadratics& q, int lw, int lh, const std::vector<float>& ratio);

}  // namespace ahd

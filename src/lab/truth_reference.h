// A path-traced reference (scripts/truth/bake_truth.py, docs/accuracy-real-lighting.md):
// per lightmap texel, Cycles' irradiance for a fixed set of tangent-space normals, some of which are
// held out as ground truth, plus the irradiance at a bumpy normal-mapped normal field. Lab code: the
// `report truth` command measures every representation against it (lab/truth_file.h reads one).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <ahd/types.h>

#include "fit/fit_image.h"

namespace ahd {

struct TruthSet {
  std::string name;  // the scene ("area", "sun")
  int width = 0, height = 0;
  std::vector<std::array<double, 3>> normals;  // unit, tangent frame of the lightmap UVs (z = normal)
  std::vector<uint8_t> held_out;               // per normal: 1 = ground truth only, 0 = training
  std::vector<std::vector<float>> e;           // per normal: width*height*3 irradiance E (no 1/π)
  std::vector<float> bumped_e;                 // width*height*3: E at the bumped normals
  std::vector<float> bumped_n;                 // width*height*3: those unit normals
  std::vector<uint8_t> coverage;               // width*height

  size_t texels() const { return size_t(width) * size_t(height); }
};

// What a baker would store from the training normals: per texel and colour channel, the
// non-negative radiance over the upper hemisphere (64 bins) whose irradiance best matches the
// training normals' (Tikhonov-regularised, projected gradient), projected onto `coeffs` (4 or 9)
// radiance SH coefficients in the tangent frame. Deterministic for any thread count.
ShImage baker_sh(const TruthSet& t, int coeffs, int threads);

// A representation: its irradiance for texel i and the tangent-space unit normal n.
using TruthEval = std::function<void(size_t i, const double n[3], double out[3])>;

// Relative L1 error Σ|I − E| / Σ|E| over covered texels and RGB: at the held-out normals, and at
// the bumped normal field.
struct TruthErrors {
  double held_out = 0, bumped = 0;
};
TruthErrors truth_errors(const TruthSet& t, const TruthEval& eval);

// What a representation shows halfway between two adjacent texels i and j (a GPU's bilinear filter
// there: the stored planes averaged, then decoded), for the tangent-space unit normal n.
using TruthPairEval = std::function<void(size_t i, size_t j, const double n[3], double out[3])>;
// A linear representation's pair: the mean of its two texels' values.
TruthPairEval mean_of_pair(const TruthEval& eval);
// Relative L1 error Σ|I − E| / Σ|E| halfway between every two horizontally or vertically adjacent
// covered texels, at the held-out normals, against the mean of the two texels' path-traced values
// (the lighting between texel centres as a bilinear lightmap would hold it): what filtering the
// stored planes costs, which the texel-centre errors do not see.
double truth_between_error(const TruthSet& t, const TruthPairEval& eval);

// A fitted image's irradiance at texel i (decode_irradiance of its planes).
TruthEval ahd_image_eval(const AhdImage& a, double dz_min);
// The planes of texels i and j averaged (what a bilinear filter holds halfway between them) into m:
// I_z 0–2, d 3–5 (not normalised: the decoder normalises it, as the shaders do after the filter),
// ratio 6–8. iz and d hold 3 floats a texel, r `rs` (1 or 3).
void truth_mid_planes(const float* iz, const float* d, const float* r, size_t i, size_t j, size_t rs, float m[9]);
// A fitted image halfway between texels i and j (truth_mid_planes, then decode_irradiance).
TruthPairEval ahd_image_pair_eval(const AhdImage& a, double dz_min);

// The constrained AHD with d searched per texel (the reference a direction choice is judged by):
// of `count` directions (Fibonacci over the hemisphere, horizon rule applied) the one with the
// lowest constrained hemisphere error against the SH, colours by fit_colours (I_z exact, C ≥ 0;
// the luminance form's least-squares ratio). Uncovered texels get fit_texel's linear fit.
AhdImage searched_direction_fit(const ShImage& sh, const FitOptions& opt, int count);

}  // namespace ahd

// What an input SH says about itself, and the warnings it earns (docs/godot.md "Damaged or
// unsuitable SH"): the sign and exact zeros of each L1 coefficient over the lit covered texels,
// and the share of texels where the fit's horizon-tilted and negative-I_z rules fired. Bad data is said, not converted in
// silence: L1 clamped at 0 (Godot's denoiser, godotengine/godot#82655) or inconsistent with the
// normals converts to direction planes that are wrong, with nothing else to show it.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <ahd/types.h>

#include "fit/fit_image.h"

namespace ahd {

// Counts over the values of each L1 coefficient (index 0, 1, 2 = y, z, x: ahd's and Godot's
// layer order) at covered texels whose L0 of the same colour is positive (a black texel's L1 is 0
// by right). Counts, not fractions, so that pages add up.
struct L1Figures {
  size_t values[3] = {};
  size_t negative[3] = {};
  size_t zero[3] = {};  // exactly 0 (+0 or -0)

  bool measured() const { return values[0] + values[1] + values[2] > 0; }
  L1Figures& operator+=(const L1Figures& o);
};

// The figures of `sh` (no L1: all zero, measured() false). Pure; thread-compatible.
L1Figures measure_l1(const ShImage& sh);

// Thresholds of the warnings (docs/godot.md "Damaged or unsuitable SH": measured there on real bakes).
constexpr double kL1ZeroShareDamaged = 0.20;  // a layer with ≥ 20 % exact zeros and no negative value anywhere
constexpr double kRulesShareWarned = 0.03;    // horizon-tilted + negative I_z on > 3 % of covered texels
constexpr size_t kFewestTexelsJudged = 64;    // fewer lit covered texels: too few to judge

// (horizon-tilted + negative I_z) / covered texels of the fit (0 when nothing is covered).
double rules_share(const FitStats& s);

// The warnings the figures earn, one sentence each naming the cause and what to do (empty when
// the data looks sound). `coeffs`: the input's coefficients (1: no L1, nothing to judge).
std::vector<std::string> sh_input_warnings(const L1Figures& l1, const FitStats& fit, int coeffs);

}  // namespace ahd

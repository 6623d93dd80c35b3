// Beyond the paper (issue 18): the direction d and the luminance ratio chosen to minimise the
// constrained fit's own hemisphere error, instead of the optimal linear direction and L(C_a)/L(I_z).
// Every constraint of the paper's fit still holds for whatever d this picks: I_z is stored exactly,
// C_a, C_d ≥ 0, and d_z ≥ dz_min (the horizon rule), so filtering never over-shoots.
#pragma once
#include <string>

#include "fit/ahd_fit.h"
#include "fit/branchless.h"

namespace ahd {

// "linear" / "refined" (the CLI's --direction-fit values and the intermediate's attribute).
const char* direction_fit_name(DirectionFit f);
// Parses a direction_fit_name(); false for anything else.
bool parse_direction_fit(const std::string& s, DirectionFit* out);

// The d-dependent hemisphere moments of the three channels at once (see HemisphereMoments):
// g1 = ∫ g, g2 = ∫ g², f1[c] = ∫ E_c g over Ω+, g = max(0, ω·d). d unit, d_z > 0. Also the lune's
// shape, for the gradient (refine_objective.h): d = (s·cos φ, s·sin φ, c), B = π − atan2(s, c)
// (for d_z > 0 atan2 is a polynomial form within 1e-15 of libm's).
// (No member initialisers: the refinement keeps arrays of these on the stack per evaluation.)
struct LuneMoments {
  double g1, g2, f1[3];
  double s, c, B;
};
LuneMoments lune_moments(const IrradiancePoly p[3], const double d[3]);
// lune_moments for the n directions d[i] into out[i], stage by stage (their latencies overlap); the
// same bytes as n single calls.
void lune_moments(const IrradiancePoly p[3], const double* const* d, int n, LuneMoments* out);
// The same with each direction's own polynomials: out[i] = lune_moments(p[i], d[i]) (p[i] points
// to three channels), for several texels' directions in one batch (refine_direction_lanes).
void lune_moments_lanes(const IrradiancePoly* const* p, const double* const* d, int n, LuneMoments* out);

// ∫_{Ω+} E for one channel (HemisphereMoments::f0; independent of d).
double hemisphere_integral(const IrradiancePoly& p);
// ∫_{Ω+} E² for one channel (HemisphereMoments::f2; independent of d).
double hemisphere_square_integral(const IrradiancePoly& p);

// The luminance-form ratio r ∈ [0,1] minimising Σ_c ∫ (r I_c + (1−r) I_c g/d_z − E_c)², the
// hemisphere error summed over the three channels (a clamped 1-D least squares). f0[c] = ∫ E_c.
// Returns 1 when every iz[c] is 0. least_squares_ratio_k: the same with k = 1.0 / dz already at
// hand (the same bytes). Inline: the refinement asks for it at every direction it evaluates.
inline double least_squares_ratio_k(const LuneMoments& m, const double f0[3], const double iz[3], double k) {
  // With C_a = r I, C_d = (1−r) I k (k = 1/d_z), E_c(r) is quadratic in r; summing dE_c/dr = 0
  // over the channels gives r = num / den.
  const double g0 = 2.0 * kPi;
  const double hh = g0 - 2.0 * k * m.g1 + k * k * m.g2;  // ∫ (1 − g/d_z)² ≥ 0
  double num = 0, den = 0;
  for (int c = 0; c < 3; ++c) {
    const double I = iz[c];
    if (!(I > 0.0)) continue;
    num += I * (I * (k * k * m.g2 - k * m.g1) + f0[c] - k * m.f1[c]);
    den += I * I * hh;
  }
  if (!(den > 0.0)) return 1.0;
  const double r = num / den;
  // r > 0 ? std::min(r, 1.0) : 0 (also maps NaN to 0), without branches (fit/branchless.h).
  return positive_part(less_or_second(1.0, r));
}

inline double least_squares_ratio(const LuneMoments& m, const double f0[3], const double iz[3], double dz) {
  return least_squares_ratio_k(m, f0, iz, 1.0 / dz);
}

// Σ_c ∫_{Ω+} (C_a + C_d max(0,ω·d) − E_c)² minus the d-independent Σ_c ∫ E_c², for the colours the
// fit of `opt`'s ratio form chooses at the unit direction d (d_z > 0) with irradiance iz along z:
// the objective refine_direction minimises.
double constrained_error(const IrradiancePoly p[3], const double iz[3], const double d[3], const FitOptions& opt);

// From the unit direction d (d_z ≥ dz_min, usually the optimal linear one) moves d to a nearby
// direction with a lower constrained hemisphere error Σ_c E_c for the ratio form of `opt` (RGB:
// each channel's own constrained optimum; luminance: least_squares_ratio). Newton steps in the
// tangent plane with the analytic gradient (refine_objective.h), started from the best of d and
// the global starts of RefineSearch (all after the horizon rule); never returns a worse d than it
// was given, and the result satisfies d_z ≥ dz_min. iz[c] ≥ 0.
void refine_direction(const IrradiancePoly p[3], const double iz[3], const FitOptions& opt, double d[3]);

// The global starts tried beside the given d (bits), and how many Newton steps follow; the
// defaults are what refine_direction uses. For measurement (`winner`, when not null: 0 = the
// given d, 1–3 = channel L1, 4 = the L2 axis facing the L1 band, 5 = the other sign, was the
// best start).
enum RefineStart : unsigned { kStartChannelL1 = 1, kStartL2Axis = 2, kStartL2AxisBoth = 4 };
struct RefineSearch {
  unsigned starts = kStartChannelL1 | kStartL2Axis | kStartL2AxisBoth;
  int steps = 2;
  bool line = true;  // Newton along −∇f (2 gradients a step); false: the 2-D Newton step (3 gradients)
  // A start within ≈ 8° of one already listed (cosine above this) is dropped: it would end in the
  // same basin (docs/notes/fit-speed-rounds.md "Speed, second round").
  double same_start_cos = 0.99;
  // Line search only: a further step only after the last lowered f by more than this fraction of
  // Σ_c 2π I_c² (most texels gain little from the second step).
  double next_step_gain = 1e-2;
};
// With `moments`, also the lune moments of the returned d (for fit_colours: the line search hands
// on those it computed; the 2-D search recomputes them).
void refine_direction(const IrradiancePoly p[3], const double iz[3], const FitOptions& opt, double d[3],
                      const RefineSearch& search, int* winner = nullptr, LuneMoments* moments = nullptr);

// refine_direction with the default RefineSearch for n ≤ kRefineLanes texels at once, in lockstep
// (one texel's steps wait on each other's square roots and divisions; several texels' overlap):
// lane k (polynomials p[k], irradiance iz[k], direction d[k] in/out, and with `moments` their
// moments into moments[k]) gets the same bytes as refine_direction alone. With `start_value`, lane
// k's objective at the d it was given, the first start's, into start_value[k]: the bits
// RefineObjective(p[k], iz[k], opt.ratio_form).value(d[k]) returns (direction_coherence.h reuses it).
constexpr int kRefineLanes = 4;
void refine_direction_lanes(int n, const IrradiancePoly* const* p, const double* const* iz, const FitOptions& opt,
                            double* const* d, LuneMoments* moments, double* start_value = nullptr);

}  // namespace ahd

// Beyond the paper (issue 18): the direction d and the luminance ratio chosen to minimise the
// constrained fit's own hemisphere error, instead of the optimal linear direction and L(C_a)/L(I_z).
// Every constraint of the paper's fit still holds for whatever d this picks: I_z is stored exactly,
// C_a, C_d ≥ 0, and d_z ≥ dz_min (the horizon rule), so filtering never over-shoots.
#pragma once
#include <string>

#include "fit/ahd_fit.h"

namespace ahd {

// "linear" / "refined" (the CLI's --direction-fit values and the intermediate's attribute).
const char* direction_fit_name(DirectionFit f);
// Parses a direction_fit_name(); false for anything else.
bool parse_direction_fit(const std::string& s, DirectionFit* out);

// The d-dependent hemisphere moments of the three channels at once (see HemisphereMoments):
// g1 = ∫ g, g2 = ∫ g², f1[c] = ∫ E_c g over Ω+, g = max(0, ω·d). d unit, d_z > 0.
struct LuneMoments {
  double g1, g2, f1[3];
};
LuneMoments lune_moments(const IrradiancePoly p[3], const double d[3]);

// ∫_{Ω+} E for one channel (HemisphereMoments::f0; independent of d).
double hemisphere_integral(const IrradiancePoly& p);

// The luminance-form ratio r ∈ [0,1] minimising Σ_c ∫ (r I_c + (1−r) I_c g/d_z − E_c)², the
// hemisphere error summed over the three channels (a clamped 1-D least squares). f0[c] = ∫ E_c.
// Returns 1 when every iz[c] is 0.
double least_squares_ratio(const LuneMoments& m, const double f0[3], const double iz[3], double dz);

// Σ_c ∫_{Ω+} (C_a + C_d max(0,ω·d) − E_c)² minus the d-independent Σ_c ∫ E_c², for the colours the
// fit of `opt`'s ratio form chooses at the unit direction d (d_z > 0) with irradiance iz along z:
// the objective refine_direction minimises.
double constrained_error(const IrradiancePoly p[3], const double iz[3], const double d[3], const FitOptions& opt);

// From the unit direction d (d_z ≥ dz_min, usually the optimal linear one) moves d to a nearby
// direction with a lower constrained hemisphere error Σ_c E_c for the ratio form of `opt` (RGB:
// each channel's own constrained optimum; luminance: least_squares_ratio). A few Newton steps on
// a local quadratic model in the tangent plane, started from the best of d, each channel's L1
// direction and the two signs of the luminance L2 band's principal axis (all after the horizon
// rule); never returns a worse d than it was given, and
// the result satisfies d_z ≥ dz_min. iz[c] ≥ 0.
void refine_direction(const IrradiancePoly p[3], const double iz[3], const FitOptions& opt, double d[3]);

}  // namespace ahd

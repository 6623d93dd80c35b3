// The constrained AHD fit of Sloan & Silvennoinen 2018 (§3), one texel at a time.
//
// Model: I(n) = C_a + max(0, n·d) C_d, per colour channel, n in the texel's local frame (z = normal).
// Stored: I_z = C_a + d_z C_d (exact, linear under filtering), d, and ratio = C_a / I_z (RGB form) or
// L(C_a)/L(I_z) (luminance form). Decode: fit/ahd_decode.h.
#pragma once
#include <cmath>
#include <limits>
#include <ahd/types.h>
#include <cstdint>

#include "sh/sh.h"

namespace ahd {


// How d (and the luminance ratio) are chosen. Linear: the paper's choice, the optimal linear
// direction of the luminance L1 band, and ratio = L(C_a)/L(I_z) of the per-channel fits. Refined:
// d moved from there to minimise the constrained fit's own hemisphere error, and the luminance
// ratio the one that minimises that error over the three channels (fit/direction_refine.h).

struct FitOptions {
  // Luminance weights for the direction and the luminance ratio (Rec.709 by default).
  double luma[3] = {0.2126, 0.7152, 0.0722};
  // Smallest d_z the encoder stores. Decoding divides by d_z; keeping d_z ≥ eps bounds
  // C_d ≤ I_z / eps. Chosen by measurement (docs/accuracy.md "Choosing ε, the horizon rule"; `ahdpack report eps`).
  double dz_min = 0.05;
  // |L1 luminance| below this fraction of the L0 luminance means "no preferred direction": d = z.
  double no_direction_threshold = 1e-6;
  RatioForm ratio_form = RatioForm::Luminance;
  // The fit stage's own default, the paper's direction; a conversion's is ConversionOptions'
  // (refined), which PipelineOptions and the option table (api/option_table.h) carry.
  DirectionFit direction_fit = DirectionFit::Linear;
  // Refined only, over an image (fit_image): a texel takes its neighbourhood's mean direction when
  // that costs at most this fraction of its constrained hemisphere error (direction_coherence.h;
  // 0 = off). Chosen by measurement (docs/fit.md "Choosing the direction beyond the paper").
  double coherence_tolerance = 0.02;
  // Refined only, over an image (fit_image): after the coherence pass, any two adjacent texels whose
  // directions turn by more than max(this, their linear directions' angle) in degrees both fall back
  // to the linear fit, until no pair does (direction_guard.h; 0 = off). Off by default since issue
  // 43: on the path-traced scenes of docs/accuracy-real-lighting.md it reverted most texels of the
  // Cornell boxes to the linear fit (with the window, up to +22 % error), and the error between
  // texels (the planes filtered) is no lower with it.
  double pair_guard_deg = 0.0;
  // Refined only, over an image (fit_image): d is chosen on the mean SH of the texel's covered
  // (2r+1)² window of this radius r and the colours on the texel's own SH (direction_filter.h; 0 =
  // each texel's own SH, with the coherence pass). 0 by default since issue 43: each texel's own
  // refined d is within the per-texel searched floor (or below it) on every scene of the truth
  // corpus, noisy ones included, and the window was not (docs/accuracy-real-lighting.md).
  int direction_window = 0;
};

// Why a texel needed a rule (bits of AhdFit::flags; counted in FitStats).
enum FitFlag : uint8_t {
  kFitNoDirection = 1,     // L1 ≈ 0: d = z
  kFitDirClamped = 2,      // d_z < dz_min (grazing or below the horizon): d tilted up to d_z = dz_min
  kFitNegativeIz = 4,      // I_z < 0 in some channel (SH ringing): that channel stored as 0
  kFitBlack = 8,           // L(I_z) == 0: ratio set to 1 (pure ambient) by convention
  kFitNonFinite = 16,      // NaN/Inf reached the fit: that channel stored as 0
};

// One fitted texel: what the planes store, before quantisation (a fitted level is held whole while
// it is quantised — as planes, fit_image.h's AhdImage — so the colours are derived, not stored).
struct AhdFit {
  float iz[3];     // irradiance along the local z (the normal), RGB
  float d[3];      // unit highlight direction, local frame, d[2] ≥ dz_min
  float ratio[3];  // C_a / I_z per channel (all three equal in the luminance form), in [0,1]
  uint8_t flags;   // FitFlag bits
};

// The colours the stored (ratio, d, I_z) decode to at the texel centre (ahd_decode.h; d_z ≥ dz_min
// already holds): ambient C_a = ratio·I_z ≥ 0 and highlight C_d = (I_z − C_a) / d_z ≥ 0.
inline double fitted_ca(const AhdFit& f, int c) { return double(f.ratio[c]) * double(f.iz[c]); }
inline double fitted_cd(const AhdFit& f, int c) { return (double(f.iz[c]) - fitted_ca(f, c)) / double(f.d[2]); }

// The hemisphere moments one texel's fit needs, exposed for tests and the unconstrained baseline.
// Integrals over the upper hemisphere Ω+ (z ≥ 0) with g(ω) = max(0, ω·d):
struct HemisphereMoments {
  double g0;  // ∫ 1      = 2π
  double g1;  // ∫ g
  double g2;  // ∫ g²
  double f0;  // ∫ E
  double f1;  // ∫ E g
  double f2;  // ∫ E²  (only needed to evaluate E(t); 0 when not requested)
};
HemisphereMoments hemisphere_moments(const IrradiancePoly& p, const double d[3], bool with_f2 = true);

// Optimal linear direction of the luminance L1 band of the three channel polynomials.
// Returns false (and d = z) when the L1 luminance is below the threshold.
bool optimal_direction(const IrradiancePoly p[3], const FitOptions& opt, double d[3]);

// The d that fit_texel with DirectionFit::Linear stores (optimal_direction after the horizon rule,
// as floats; z when there is no direction), without the colours: what the refined fit's pair guard
// compares against (direction_guard.h).
void linear_direction(const IrradiancePoly p[3], const FitOptions& opt, float d[3]);

// The closed-form minimiser of E(t) (eq. 12) for one channel, clamped to [t_min, t_max]
// (C_a ≥ 0, C_d ≥ 0); writes C_a, C_d. Requires iz ≥ 0 and d[2] > 0.
void fit_channel(const HemisphereMoments& m, double iz, double dz, double* ca, double* cd, double* t = nullptr);

// E(t)/(2π) for one channel: the mean squared hemisphere error of the AHD lobe (C_a, C_d) with the
// direction the moments were computed for.
double hemisphere_mse(const HemisphereMoments& m, double ca, double cd);

// The colour part of the fit for a GIVEN direction d (unit, d[2] ≥ dz_min) and GIVEN irradiance
// along the normal iz[c] ≥ 0 (the closed-loop quantiser passes the decoded d and I_z here).
// The luminance ratio follows opt.direction_fit (Refined: the least-squares ratio).
AhdFit fit_colours(const IrradiancePoly p[3], const double d[3], const double iz[3], const FitOptions& opt);
// The same with d's lune moments already at hand (refined only: lune_moments(p, d) of
// direction_refine.h, which the refinement returns): the same bytes without recomputing them.
struct LuneMoments;
AhdFit fit_colours(const IrradiancePoly p[3], const double d[3], const double iz[3], const FitOptions& opt,
                   const LuneMoments* moments);

// Fits one texel from its three channel polynomials (local frame). Always finite output for
// finite input; constraints always hold (C_a, C_d ≥ 0, ratio in [0,1], d_z ≥ dz_min).
AhdFit fit_texel(const IrradiancePoly p[3], const FitOptions& opt);
// The same, also writing linear_direction(p, opt) to linear_d (when not null) from the d it
// computes on the way (fit_image's pair guard needs it beside a refined fit).
AhdFit fit_texel(const IrradiancePoly p[3], const FitOptions& opt, float linear_d[3]);
// fit_texel for n ≤ 4 texels at once (kRefineLanes of direction_refine.h): texel k's polynomials
// are p[3k..3k+3), its fit goes to out[k] and, when linear_d is not null, its linear d to
// linear_d[3k..3k+3). The same bytes as n fit_texel calls; the refined fit runs the texels'
// searches in lockstep (faster per texel). With `linear_value`, texel k's refinement objective at
// its linear d (refine_direction_lanes' start_value) into linear_value[k], NaN where the texel was
// not refined (no direction, constant irradiance, or the linear fit).
void fit_texels(const IrradiancePoly* p, int n, const FitOptions& opt, AhdFit* out, float* linear_d,
                double* linear_value = nullptr);

// What fit_texels decides before the colours: the direction, I_z and the direction stage's flags of
// each texel, without solving its colours (the windowed fit, fit_image.cpp, solves them on other
// SH). For texel k, with f = fit_texels' out[k]: d and iz are f.d and f.iz bit for bit, and flags
// is f.flags without kFitBlack (which the colour solve adds), except where `constant` (irradiance
// the same for every normal: fit_texel_constant's texel, whose flags are f.flags whole). linear_d
// as fit_texels writes it. The same bytes at any n ≤ 4.
struct FitDirection {
  float d[3];
  float iz[3];
  uint8_t flags;
  bool constant;
};
void fit_directions(const IrradiancePoly* p, int n, const FitOptions& opt, FitDirection* out, float* linear_d);

// What fit_texel returns for a texel whose irradiance is the same for every normal (only e0
// nonzero: every texel of an L0 image): the pure ambient lobe, exact with nothing to solve —
// I_z = E(z) (non-finite or negative → 0, flagged), d = z, ratio = 1, flag kFitNoDirection.
AhdFit fit_texel_constant(const IrradiancePoly p[3], const FitOptions& opt);

// I_z = E(z) per channel, made usable: non-finite → 0 (kFitNonFinite in *flags), negative (SH
// ringing: no non-negative lobe reaches it) → 0 with *negative set.
inline void usable_iz(const double ez[3], double iz[3], uint8_t* flags, bool* negative) {
  *negative = false;
  for (int c = 0; c < 3; ++c) {
    iz[c] = ez[c];
    if (!std::isfinite(iz[c])) {
      iz[c] = 0.0;  // readers sanitise; this keeps the fit total even when called directly
      *flags |= kFitNonFinite;
    } else if (iz[c] < 0.0) {
      iz[c] = 0.0;
      *negative = true;
    }
  }
}

// fit_texel_constant from E(z) per channel (ez: the irradiance along the normal, any value).
// Inline: the per-texel loops of plain lightmaps call it for every texel.
inline AhdFit fit_constant_irradiance(const double ez[3], const FitOptions& opt) {
  AhdFit out{};
  out.d[2] = 1.0f;
  for (int c = 0; c < 3; ++c) out.ratio[c] = 1.0f;
  out.flags = kFitNoDirection;
  double iz[3];
  bool negative;
  usable_iz(ez, iz, &out.flags, &negative);
  for (int c = 0; c < 3; ++c) out.iz[c] = float(iz[c]);
  const double lum_iz = opt.luma[0] * iz[0] + opt.luma[1] * iz[1] + opt.luma[2] * iz[2];
  if (!(lum_iz > 0.0)) out.flags |= kFitBlack;
  if (negative) out.flags |= kFitNegativeIz;
  return out;
}

// fit_constant_irradiance's I_z for one channel of an L0 texel in its own frame, E(z) =
// l0_irradiance(c0) + 0 (non-finite or negative → 0), without the flags: the hot loops of plain
// lightmaps (tests compare it with the general route).
inline float l0_texel_iz(float c0) {
  const double ez = l0_irradiance(c0) + 0.0;
  return ez > 0.0 && ez <= std::numeric_limits<double>::max() ? float(ez) : 0.0f;
}

// The unconstrained least-squares fit over the hemisphere (Sloan 2008 style) with the same d:
// free C_a, C_d minimising E; may be negative and does not preserve I_z. For comparison only.
void fit_channel_unconstrained(const HemisphereMoments& m, double* ca, double* cd);

}  // namespace ahd

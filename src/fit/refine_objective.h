// The objective of the direction refinement (direction_refine.h) and its gradient over d, both in
// closed form through the lune integrals of hemisphere_moments.cpp.
//
// f(d) = Σ_c ∫_{Ω+} (C_a + C_d max(0,ω·d) − E_c)² − Σ_c ∫ E_c², at the colours the fit chooses for d.
// Gradient: written with a_c = C_a ∈ [0, I_c] (a box that does not depend on d) and
// C_d = (I_c − a_c)/d_z, the optimal a_c's own change does not move f (envelope theorem), so
//   ∂f/∂d = Σ_c b² ∇G2 + 2ab ∇G1 − 2b ∇F1_c  +  e_z Σ_c (−2b/d_z)(b G2 + a G1 − F1_c),
// b = C_d, with ∇G1 = ∫_lune ω, ∇G2 = 2∫_lune (ω·d) ω, ∇F1 = ∫_lune E ω (the boundary terms vanish
// because ω·d = 0 on the lune's edge): monomials of degree ≤ 3 over the same lune.
#pragma once
#include "fit/ahd_fit.h"
#include "fit/direction_refine.h"

namespace ahd {

struct RefineObjective {
  const IrradiancePoly* p;  // the three channels' polynomials (local frame)
  double iz[3];             // irradiance along z, ≥ 0
  double f0[3];             // ∫_{Ω+} E_c (hemisphere_integral)
  bool luminance;           // ratio form: luminance (least_squares_ratio) or RGB (per channel)

  RefineObjective(const IrradiancePoly p3[3], const double iz3[3], RatioForm form);
  RefineObjective() : p(nullptr), iz{}, f0{}, luminance(false) {}  // to be assigned before use

  // f(d) for a unit d with d_z > 0.
  double value(const double d[3]) const;
  // value(d[i]) into out[i] for n directions at once (lune_moments' batch form): the same bytes.
  // With `moments` (n entries) also each direction's lune moments, for gradient_at / fit_colours.
  void values(const double* const* d, int n, double* out, LuneMoments* moments = nullptr) const;
  // f(d) from d's lune moments m (d_z = dz): what values() computes after lune_moments, the same bytes.
  double value_at(const LuneMoments& m, double dz) const;
  // f(d) and its gradient on the unit sphere (a tangent vector at d, world/local frame).
  // With `moments`, also d's lune moments.
  double value_grad(const double d[3], double grad[3], LuneMoments* moments = nullptr) const;
  // The gradient alone at d from d's lune moments m (lune_moments(p, d)): the same bytes as
  // value_grad's.
  void gradient_at(const double d[3], const LuneMoments& m, double grad[3]) const;
  // The colours the fit chooses at d (d_z = dz) from d's lune moments: a = C_a, b = C_d per channel
  // (C_a ∈ [0, I_c], C_a + d_z C_d = I_c up to rounding).
  void colours(const LuneMoments& m, double dz, double a[3], double b[3]) const;

 private:
  void gradient(const double d[3], const LuneMoments& m, const double a[3], const double b[3], double grad[3]) const;
};

// out[i] = f[i]->value_at(m[i], dz[i]) for n evaluations (each with its own objective, e.g.
// several texels'), stage by stage so that their divisions overlap: the same bytes.
void values_at_lanes(const RefineObjective* const* f, const LuneMoments* m, const double* dz, int n, double* out);

}  // namespace ahd

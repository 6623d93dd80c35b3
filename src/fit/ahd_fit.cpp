#include "fit/ahd_fit.h"

#include "fit/ahd_decode.h"
#include "fit/direction_refine.h"
#include "fit/refine_objective.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ahd {

bool optimal_direction(const IrradiancePoly p[3], const FitOptions& opt, double d[3]) {
  double v[3] = {0, 0, 0};
  double l0 = 0;
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < 3; ++i) v[i] += opt.luma[c] * p[c].e[i];
    l0 += opt.luma[c] * p[c].e0;
  }
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  // Relative test against L0 so that the rule is scale-invariant; the absolute floor catches
  // L0 = 0 with denormal-level L1, where a direction would be noise.
  if (!(len > opt.no_direction_threshold * std::fabs(l0)) || len < 1e-30) {
    d[0] = 0, d[1] = 0, d[2] = 1;
    return false;
  }
  for (int i = 0; i < 3; ++i) d[i] = v[i] / len;
  return true;
}

void linear_direction(const IrradiancePoly p[3], const FitOptions& opt, float d[3]) {
  double v[3];
  optimal_direction(p, opt, v);
  tilt_above_horizon(v, opt.dz_min);
  for (int i = 0; i < 3; ++i) d[i] = float(v[i]);
}

void fit_channel(const HemisphereMoments& m, double iz, double dz, double* ca, double* cd, double* t_out) {
  // General solution of [1 d_z][C_a C_d]ᵀ = I_z (eq. 11): C_a = a0 − d_z t, C_d = b0 + t.
  const double k = 1.0 / (dz * dz + 1.0);
  const double a0 = iz * k, b0 = iz * dz * k;
  // E(t) = ∫ (R0 + t h)² with R0 = a0 + b0 g − E and h = g − d_z: quadratic in t.
  const double hh = m.g2 - 2.0 * dz * m.g1 + dz * dz * m.g0;
  const double rh = a0 * m.g1 + b0 * m.g2 - m.f1 - dz * (a0 * m.g0 + b0 * m.g1 - m.f0);
  double t = hh > 0 ? -rh / hh : 0.0;
  // Feasible interval: C_d ≥ 0 ⇔ t ≥ −b0;  C_a ≥ 0 ⇔ t ≤ a0/d_z.
  const double t_min = -b0, t_max = a0 / dz;
  if (!(t >= t_min)) t = t_min;  // also catches NaN
  if (t > t_max) t = t_max;
  if (t == t_min) {
    *ca = iz, *cd = 0.0;
  } else if (t == t_max) {
    *ca = 0.0, *cd = iz / dz;
  } else {
    *ca = std::max(0.0, a0 - dz * t);
    *cd = std::max(0.0, b0 + t);
  }
  if (t_out) *t_out = t;
}

double hemisphere_mse(const HemisphereMoments& m, double ca, double cd) {
  const double e = ca * ca * m.g0 + cd * cd * m.g2 + m.f2 + 2.0 * ca * cd * m.g1 - 2.0 * ca * m.f0 -
                   2.0 * cd * m.f1;
  return std::max(0.0, e) / m.g0;
}

void fit_channel_unconstrained(const HemisphereMoments& m, double* ca, double* cd) {
  const double det = m.g0 * m.g2 - m.g1 * m.g1;
  *ca = (m.f0 * m.g2 - m.g1 * m.f1) / det;
  *cd = (m.g0 * m.f1 - m.g1 * m.f0) / det;
}

namespace {

// True when no channel's irradiance depends on the normal (only e0 is nonzero).
bool irradiance_is_constant(const IrradiancePoly p[3]) {
  for (int c = 0; c < 3; ++c) {
    if (p[c].e[0] != 0.0 || p[c].e[1] != 0.0 || p[c].e[2] != 0.0) return false;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (p[c].q[i][j] != 0.0) return false;
  }
  return true;
}

}  // namespace

namespace {

// E(z), the irradiance along the normal, per channel.
void irradiance_along_z(const IrradiancePoly p[3], double ez[3]) {
  for (int c = 0; c < 3; ++c) ez[c] = p[c].e0 + p[c].e[2] + p[c].q[2][2];
}

}  // namespace

AhdFit fit_texel_constant(const IrradiancePoly p[3], const FitOptions& opt) {
  double ez[3];
  irradiance_along_z(p, ez);
  return fit_constant_irradiance(ez, opt);
}

AhdFit fit_texel(const IrradiancePoly p[3], const FitOptions& opt) { return fit_texel(p, opt, nullptr); }

AhdFit fit_texel(const IrradiancePoly p[3], const FitOptions& opt, float linear_d[3]) {
  AhdFit out;
  fit_texels(p, 1, opt, &out, linear_d);
  return out;
}

namespace {

// fit_texels up to the colours: per texel up to the refinement; the texels to refine then go
// through refine_direction_lanes together (their dependent chains overlap). A texel whose
// irradiance is constant is fitted whole into out[k] (done[k]).
struct DirectionStage {
  double d[kRefineLanes][3], iz[kRefineLanes][3];
  uint8_t flags[kRefineLanes];
  bool negative[kRefineLanes], refine[kRefineLanes] = {}, done[kRefineLanes] = {};
  int lane_of[kRefineLanes];
  LuneMoments m[kRefineLanes];
};

void direction_stage(const IrradiancePoly* p, int n, const FitOptions& opt, AhdFit* out, float* linear_d,
                     DirectionStage& s, double* linear_value = nullptr) {
  const IrradiancePoly* lp[kRefineLanes];
  const double* liz[kRefineLanes];
  double* ld[kRefineLanes];
  int nl = 0;
  for (int k = 0; k < n; ++k) {
    const IrradiancePoly* pk = p + 3 * k;
    float* lin = linear_d ? linear_d + 3 * k : nullptr;
    const bool directional = optimal_direction(pk, opt, s.d[k]);
    // Irradiance the same for every normal (a plain lightmap, or no L1/L2 at this texel): the pure
    // ambient lobe is exact, so there is nothing to fit (and plain maps skip the per-channel solve).
    if (!directional && irradiance_is_constant(pk)) {
      if (lin) lin[0] = 0.0f, lin[1] = 0.0f, lin[2] = 1.0f;  // optimal_direction's z
      out[k] = fit_texel_constant(pk, opt);
      s.done[k] = true;
      continue;
    }
    s.flags[k] = directional ? 0 : kFitNoDirection;
    // Decoding divides by d_z: grazing / below-horizon directions are tilted up (ahd_decode.h).
    if (tilt_above_horizon(s.d[k], opt.dz_min)) s.flags[k] |= kFitDirClamped;
    if (lin)
      for (int i = 0; i < 3; ++i) lin[i] = float(s.d[k][i]);  // = linear_direction(p, opt)
    double ez[3];
    irradiance_along_z(pk, ez);
    usable_iz(ez, s.iz[k], &s.flags[k], &s.negative[k]);
    // Refinement keeps d_z ≥ dz_min itself; kFitDirClamped still says whether the linear d needed it.
    s.refine[k] = directional && opt.direction_fit == DirectionFit::Refined;
    if (s.refine[k]) lp[nl] = pk, liz[nl] = s.iz[k], ld[nl] = s.d[k], s.lane_of[k] = nl++;
  }
  double start_value[kRefineLanes];
  if (nl) refine_direction_lanes(nl, lp, liz, opt, ld, s.m, linear_value ? start_value : nullptr);
  if (linear_value)
    for (int k = 0; k < n; ++k)
      linear_value[k] = s.refine[k] ? start_value[s.lane_of[k]] : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

void fit_texels(const IrradiancePoly* p, int n, const FitOptions& opt, AhdFit* out, float* linear_d,
                double* linear_value) {
  DirectionStage s;
  direction_stage(p, n, opt, out, linear_d, s, linear_value);
  for (int k = 0; k < n; ++k) {
    if (s.done[k]) continue;
    const IrradiancePoly* pk = p + 3 * k;
    out[k] = s.refine[k] ? fit_colours(pk, s.d[k], s.iz[k], opt, &s.m[s.lane_of[k]]) : fit_colours(pk, s.d[k], s.iz[k], opt);
    out[k].flags |= s.flags[k] | (s.negative[k] ? kFitNegativeIz : 0);
  }
}

void fit_directions(const IrradiancePoly* p, int n, const FitOptions& opt, FitDirection* out, float* linear_d) {
  DirectionStage s;
  AhdFit whole[kRefineLanes];
  direction_stage(p, n, opt, whole, linear_d, s);
  for (int k = 0; k < n; ++k) {
    FitDirection& o = out[k];
    o.constant = s.done[k];
    if (s.done[k]) {
      for (int i = 0; i < 3; ++i) o.d[i] = whole[k].d[i], o.iz[i] = whole[k].iz[i];
      o.flags = whole[k].flags;
      continue;
    }
    // As fit_colours stores them; the flags fit_texels adds to the colours' (all but kFitBlack).
    for (int i = 0; i < 3; ++i) o.d[i] = float(s.d[k][i]), o.iz[i] = float(s.iz[k][i]);
    o.flags = s.flags[k] | (s.negative[k] ? kFitNegativeIz : 0);
  }
}

AhdFit fit_colours(const IrradiancePoly p[3], const double d[3], const double iz[3], const FitOptions& opt) {
  return fit_colours(p, d, iz, opt, nullptr);
}

AhdFit fit_colours(const IrradiancePoly p[3], const double d[3], const double iz[3], const FitOptions& opt,
                   const LuneMoments* moments) {
  AhdFit out{};
  const double dz = d[2];
  for (int i = 0; i < 3; ++i) out.d[i] = float(d[i]);
  const double lum_iz = opt.luma[0] * iz[0] + opt.luma[1] * iz[1] + opt.luma[2] * iz[2];
  if (!(lum_iz > 0.0)) out.flags |= kFitBlack;
  double ratio[3] = {1.0, 1.0, 1.0};
  if (opt.direction_fit == DirectionFit::Refined) {
    // The colours the refinement's objective chose at d (refine_objective.h), from the moments of
    // the three channels at once (closed forms): the arithmetic the refinement minimised. The
    // luminance ratio is the least-squares one.
    const RefineObjective f(p, iz, opt.ratio_form);
    const LuneMoments lm = moments ? *moments : lune_moments(p, d);
    if (opt.ratio_form == RatioForm::Luminance) {
      const double r = lum_iz > 0.0 ? least_squares_ratio(lm, f.f0, iz, dz) : 1.0;
      ratio[0] = ratio[1] = ratio[2] = r;
    } else {
      double ca[3], cd[3];
      f.colours(lm, dz, ca, cd);
      for (int c = 0; c < 3; ++c) ratio[c] = iz[c] > 0.0 ? std::clamp(ca[c] / iz[c], 0.0, 1.0) : 1.0;
    }
  } else {
    // The paper's fit: per channel, then L(C_a)/L(I_z) in the luminance form.
    double ca[3] = {0, 0, 0}, cd[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) {
      if (!(iz[c] > 0.0)) continue;
      const HemisphereMoments m = hemisphere_moments(p[c], d, /*with_f2=*/false);
      fit_channel(m, iz[c], dz, &ca[c], &cd[c]);
    }
    if (opt.ratio_form == RatioForm::Luminance) {
      const double lum_ca = opt.luma[0] * ca[0] + opt.luma[1] * ca[1] + opt.luma[2] * ca[2];
      const double r = lum_iz > 0.0 ? std::clamp(lum_ca / lum_iz, 0.0, 1.0) : 1.0;
      ratio[0] = ratio[1] = ratio[2] = r;
    } else {
      for (int c = 0; c < 3; ++c) ratio[c] = iz[c] > 0.0 ? std::clamp(ca[c] / iz[c], 0.0, 1.0) : 1.0;
    }
  }
  for (int c = 0; c < 3; ++c) {
    out.iz[c] = float(iz[c]);
    out.ratio[c] = float(ratio[c]);
  }
  return out;
}

}  // namespace ahd

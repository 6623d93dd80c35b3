#include "fit/refine_objective.h"

#include <algorithm>
#include <cmath>

#include "fit/branchless.h"
#include "fit/direction_refine.h"

namespace ahd {

RefineObjective::RefineObjective(const IrradiancePoly p3[3], const double iz3[3], RatioForm form)
    : p(p3), luminance(form == RatioForm::Luminance) {
  for (int c = 0; c < 3; ++c) iz[c] = iz3[c], f0[c] = hemisphere_integral(p3[c]);
}

namespace {

// choose_colours in stages, so that a batch's divisions overlap (values_at_lanes): first the
// division (luminance: k = 1/d_z; RGB: one division for 1/(d_z² + 1), 1/hh and 1/d_z), then the
// luminance ratio (its own division), then the colours.
double colour_divisor(const RefineObjective& o, const LuneMoments& m, double dz) {
  if (o.luminance) return 1.0 / dz;
  const double g0 = 2.0 * kPi;
  const double hh = m.g2 - 2.0 * dz * m.g1 + dz * dz * g0;
  const double dz1 = dz * dz + 1.0;
  return 1.0 / (dz * dz1 * (hh > 0 ? hh : 1.0));
}

double colour_ratio(const RefineObjective& o, const LuneMoments& m, double k) {
  return o.luminance ? least_squares_ratio_k(m, o.f0, o.iz, k) : 0.0;
}

void colours_from(const RefineObjective& o, const LuneMoments& m, double dz, double k, double r, double a[3],
                  double b[3]) {
  const double g0 = 2.0 * kPi;
  if (o.luminance) {
    const double inv_dz = k;
    for (int c = 0; c < 3; ++c) {
      const double I = o.iz[c] > 0.0 ? o.iz[c] : 0.0;
      a[c] = r * I, b[c] = (I - a[c]) * inv_dz;
    }
    return;
  }
  // fit_channel's arithmetic with the channel-independent divisions hoisted out.
  const double hh = m.g2 - 2.0 * dz * m.g1 + dz * dz * g0;
  const double dz1 = dz * dz + 1.0;
  const double inv_all = k;
  const double kk = inv_all * dz * (hh > 0 ? hh : 1.0);
  const double inv_hh = hh > 0 ? inv_all * dz * dz1 : 0.0;
  const double inv_dz = inv_all * dz1 * (hh > 0 ? hh : 1.0);
  for (int c = 0; c < 3; ++c) {
    if (!(o.iz[c] > 0.0)) {
      a[c] = b[c] = 0.0;
      continue;
    }
    const double a0 = o.iz[c] * kk, b0 = a0 * dz;
    const double rh = a0 * m.g1 + b0 * m.g2 - m.f1[c] - dz * (a0 * g0 + b0 * m.g1 - o.f0[c]);
    // std::clamp(v, lo, hi) as a max then a min (maxsd/minsd, no branch to mispredict on random
    // lighting): the same value whenever lo ≤ hi, which holds (a0 ≥ 0 or NaN, d_z > 0), NaNs included.
    const double v = -rh * inv_hh, lo = -b0, hi = a0 * inv_dz;
    const double t1 = v < lo ? lo : v;
    const double t = hi < t1 ? hi : t1;
    a[c] = positive_part(a0 - dz * t), b[c] = positive_part(b0 + t);
  }
}

// The colours the fit chooses at d (d_z = dz) from the moments: a = C_a, b = C_d.
void choose_colours(const RefineObjective& o, const LuneMoments& m, double dz, double a[3], double b[3]) {
  const double k = colour_divisor(o, m, dz);
  colours_from(o, m, dz, k, colour_ratio(o, m, k), a, b);
}

double error_sum(const RefineObjective& o, const LuneMoments& m, const double a[3], const double b[3]) {
  const double g0 = 2.0 * kPi;
  double e = 0;
  for (int c = 0; c < 3; ++c)
    e += a[c] * a[c] * g0 + b[c] * b[c] * m.g2 + 2.0 * a[c] * b[c] * m.g1 - 2.0 * a[c] * o.f0[c] -
         2.0 * b[c] * m.f1[c];
  return e;
}

}  // namespace

double RefineObjective::value(const double d[3]) const {
  double f;
  values(&d, 1, &f);
  return f;
}

void RefineObjective::values(const double* const* d, int n, double* out, LuneMoments* moments) const {
  constexpr int kBatch = 8;
  LuneMoments local[kBatch];
  for (int i0 = 0; i0 < n; i0 += kBatch) {
    const int k = std::min(kBatch, n - i0);
    LuneMoments* m = moments ? moments + i0 : local;
    lune_moments(p, d + i0, k, m);
    for (int i = 0; i < k; ++i) {
      double a[3], b[3];
      colours(m[i], d[i0 + i][2], a, b);
      out[i0 + i] = error_sum(*this, m[i], a, b);
    }
  }
}

double RefineObjective::value_at(const LuneMoments& m, double dz) const {
  double a[3], b[3];
  colours(m, dz, a, b);
  return error_sum(*this, m, a, b);
}

void values_at_lanes(const RefineObjective* const* f, const LuneMoments* m, const double* dz, int n, double* out) {
  constexpr int kBlock = 8;
  for (int i0 = 0; i0 < n; i0 += kBlock) {
    const int nb = std::min(kBlock, n - i0);
    double k[kBlock], r[kBlock];
    for (int i = 0; i < nb; ++i) k[i] = colour_divisor(*f[i0 + i], m[i0 + i], dz[i0 + i]);
    for (int i = 0; i < nb; ++i) r[i] = colour_ratio(*f[i0 + i], m[i0 + i], k[i]);
    for (int i = 0; i < nb; ++i) {
      double a[3], b[3];
      colours_from(*f[i0 + i], m[i0 + i], dz[i0 + i], k[i], r[i], a, b);
      out[i0 + i] = error_sum(*f[i0 + i], m[i0 + i], a, b);
    }
  }
}

double RefineObjective::value_grad(const double d[3], double grad[3], LuneMoments* moments) const {
  const LuneMoments m = lune_moments(p, d);
  if (moments) *moments = m;
  double a[3], b[3];
  colours(m, d[2], a, b);
  const double f = error_sum(*this, m, a, b);
  gradient(d, m, a, b, grad);
  return f;
}

void RefineObjective::gradient_at(const double d[3], const LuneMoments& m, double grad[3]) const {
  double a[3], b[3];
  colours(m, d[2], a, b);
  gradient(d, m, a, b, grad);
}

void RefineObjective::colours(const LuneMoments& m, double dz, double a[3], double b[3]) const {
  choose_colours(*this, m, dz, a, b);
}

void RefineObjective::gradient(const double d[3], const LuneMoments& m, const double a[3], const double b[3],
                               double grad[3]) const {
  // The lune frame: rotate about z by −φ so that d = (s, 0, c), s ≥ 0 (as lune_moments does).
  const double s = m.s, c = m.c, B = m.B;
  const double inv_s = s > 0 ? 1.0 / s : 0.0;
  const double cp = s > 0 ? d[0] * inv_s : 1.0, sp = d[1] * inv_s;
  // ∫_lune of the monomials ω·(1, x, z, …) with no factor ω·d (closed forms of lune_monomial, p = 0).
  const double Mx = kPi / 2 * s, Mz = kPi / 2 * (1 + c);
  const double Mxx = 2.0 / 3 * (B - s * c), Mzz = 2.0 / 3 * (B + s * c), Mxz = 2.0 / 3 * s * s, Myy = 2.0 / 3 * B;
  const double c3 = c * c * c, s3 = s * s * s;
  const double Mxxx = 3 * kPi / 8 * (s - s3 / 3), Mxxz = kPi / 8 * (1 + c3), Mxzz = kPi / 8 * s3;
  const double Mzzz = kPi / 8 * (2 + 3 * c - c3), Myyx = kPi / 8 * s, Myyz = kPi / 8 * (1 + c);
  // ∫_lune (ω·d) x and (ω·d) z (half of ∇G2).
  const double lx = 2.0 / 3 * s * B, lz = 2.0 / 3 * (c * B + s);
  // The gradient is linear in the channels' polynomials: sum them weighted by 2 C_d first, then
  // rotate and integrate one polynomial instead of three.
  double sbb = 0, sab = 0, gzz = 0;
  double w0 = 0, we[3] = {0, 0, 0}, wq00 = 0, wq01 = 0, wq11 = 0, wq22 = 0, wq02 = 0, wq12 = 0;
  for (int k = 0; k < 3; ++k) {
    if (a[k] == 0.0 && b[k] == 0.0) continue;
    const IrradiancePoly& q = p[k];
    const double b2 = 2 * b[k];
    sbb += b[k] * b[k], sab += 2 * a[k] * b[k];
    w0 += b2 * q.e0;
    for (int i = 0; i < 3; ++i) we[i] += b2 * q.e[i];
    wq00 += b2 * q.q[0][0], wq01 += b2 * q.q[0][1], wq11 += b2 * q.q[1][1], wq22 += b2 * q.q[2][2];
    wq02 += b2 * q.q[0][2], wq12 += b2 * q.q[1][2];
    gzz -= b2 * (b[k] * m.g2 + a[k] * m.g1 - m.f1[k]);  // through C_d = (I − a)/d_z (÷ d_z below)
  }
  const double cc = cp * cp, ss = sp * sp, cs = cp * sp;
  const double ex = cp * we[0] + sp * we[1], ey = -sp * we[0] + cp * we[1], ez = we[2];
  const double qxx = cc * wq00 + 2 * cs * wq01 + ss * wq11;
  const double qyy = ss * wq00 - 2 * cs * wq01 + cc * wq11;
  const double qzz = wq22;
  const double qxy = -cs * wq00 + (cc - ss) * wq01 + cs * wq11;
  const double qxz = cp * wq02 + sp * wq12, qyz = -sp * wq02 + cp * wq12;
  const double Fx = w0 * Mx + ex * Mxx + ez * Mxz + qxx * Mxxx + qyy * Myyx + qzz * Mxzz + 2 * qxz * Mxxz;
  const double Fy = ey * Myy + 2 * qxy * Myyx + 2 * qyz * Myyz;
  const double Fz = w0 * Mz + ex * Mxz + ez * Mzz + qxx * Mxxz + qyy * Myyz + qzz * Mzzz + 2 * qxz * Mxzz;
  const double gx = sbb * 2 * lx + sab * Mx - Fx;
  const double gy = -Fy;
  double gz = sbb * 2 * lz + sab * Mz - Fz;
  gz += gzz / c;
  // Back to the texel frame, then onto the tangent plane of the unit sphere at d.
  double g[3] = {cp * gx - sp * gy, sp * gx + cp * gy, gz};
  const double dot = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
  for (int i = 0; i < 3; ++i) grad[i] = g[i] - dot * d[i];
}

}  // namespace ahd

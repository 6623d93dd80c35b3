// Closed-form hemisphere integrals for the AHD fit.
//
// With d rotated into the xz-plane, d = (s, 0, c), the region where both z ≥ 0 and ω·d ≥ 0 is a
// lune whose edge is the y axis. In coordinates around that axis,
//   ω = (sin α cos β, cos α, sin α sin β),  dω = sin α dα dβ,  α ∈ [0, π],  β ∈ [0, π − θ],
// and ω·d = sin α sin(β + θ). Every monomial integral over the lune then factors into a Beta-type
// integral in α and a trigonometric integral in β over [0, B], B = π − θ, both in closed form.
#include <algorithm>
#include <cmath>

#include "fit/ahd_fit.h"
#include "fit/direction_refine.h"

namespace ahd {
namespace {

// A(m, b) = ∫_0^π sin^m α cos^b α dα for the (m, b) the fit needs (b odd → 0).
double alpha_integral(int m, int b) {
  if (b % 2) return 0.0;
  if (b == 0) {
    switch (m) {
      case 1: return 2.0;
      case 2: return kPi / 2.0;
      case 3: return 4.0 / 3.0;
      case 4: return 3.0 * kPi / 8.0;
    }
  }
  if (b == 2 && m == 2) return kPi / 8.0;  // ∫ sin² cos² = π/8
  return NAN;  // not needed by the fit
}

// S(i, j) = ∫_0^B cos^i β sin^j β dβ, i + j ≤ 3, with cos B = −c, sin B = s.
struct BetaIntegrals {
  double S[4][4];
  BetaIntegrals(double B, double s, double c) {
    const double cB = -c, sB = s;
    S[0][0] = B;
    S[1][0] = sB;
    S[0][1] = 1.0 - cB;
    S[2][0] = 0.5 * B + 0.5 * sB * cB;
    S[0][2] = 0.5 * B - 0.5 * sB * cB;
    S[1][1] = 0.5 * sB * sB;
    S[3][0] = sB - sB * sB * sB / 3.0;
    S[0][3] = (1.0 - cB) - (1.0 - cB * cB * cB) / 3.0;
    S[2][1] = (1.0 - cB * cB * cB) / 3.0;
    S[1][2] = sB * sB * sB / 3.0;
  }
};

// ∫_lune x^a y^b z^cz (ω·d)^p dω for d = (s, 0, c).
double lune_monomial(const BetaIntegrals& bi, double s, double c, int a, int b, int cz, int p) {
  // (s cos β + c sin β)^p = Σ_k C(p,k) s^k c^(p-k) cos^k β sin^(p-k) β
  static const int binom[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};
  const double sp[3] = {1.0, s, s * s}, cp[3] = {1.0, c, c * c};
  double beta_part = 0.0;
  for (int k = 0; k <= p; ++k) beta_part += binom[p][k] * sp[k] * cp[p - k] * bi.S[a + k][cz + p - k];
  return alpha_integral(a + cz + p + 1, b) * beta_part;
}

// ∫_{Ω+} x^a y^b z^c dω = Γ((a+1)/2)Γ((b+1)/2)Γ((c+1)/2)/Γ((a+b+c+3)/2) for even a, b; else 0.
// Tabulated once for exponents ≤ 4 (all the fit needs).
struct MonomialTable {
  double v[5][5][5];
  MonomialTable() {
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b)
        for (int c = 0; c < 5; ++c)
          v[a][b][c] = (a % 2 || b % 2) ? 0.0
                                        : std::tgamma((a + 1) / 2.0) * std::tgamma((b + 1) / 2.0) *
                                              std::tgamma((c + 1) / 2.0) / std::tgamma((a + b + c + 3) / 2.0);
  }
};
double hemisphere_monomial(int a, int b, int c) {
  static const MonomialTable table;
  return table.v[a][b][c];
}

// ∫_{Ω+} E² for a quadratic E: expand into monomials of degree ≤ 4.
double hemisphere_square(const IrradiancePoly& p) {
  // Coefficients of E as a polynomial: c[a][b][cz] for x^a y^b z^cz, a+b+cz ≤ 2.
  double c[3][3][3] = {};
  c[0][0][0] = p.e0;
  c[1][0][0] = p.e[0];
  c[0][1][0] = p.e[1];
  c[0][0][1] = p.e[2];
  c[2][0][0] = p.q[0][0];
  c[0][2][0] = p.q[1][1];
  c[0][0][2] = p.q[2][2];
  c[1][1][0] = 2 * p.q[0][1];
  c[1][0][1] = 2 * p.q[0][2];
  c[0][1][1] = 2 * p.q[1][2];
  double sum = 0.0;
  for (int a1 = 0; a1 < 3; ++a1)
    for (int b1 = 0; a1 + b1 < 3; ++b1)
      for (int c1 = 0; a1 + b1 + c1 < 3; ++c1) {
        if (c[a1][b1][c1] == 0.0) continue;
        for (int a2 = 0; a2 < 3; ++a2)
          for (int b2 = 0; a2 + b2 < 3; ++b2)
            for (int c2 = 0; a2 + b2 + c2 < 3; ++c2) {
              if (c[a2][b2][c2] == 0.0) continue;
              sum += c[a1][b1][c1] * c[a2][b2][c2] * hemisphere_monomial(a1 + a2, b1 + b2, c1 + c2);
            }
      }
  return sum;
}

// atan2(s, c) for s ≥ 0, c > 0 (θ ∈ [0, π/2)), within 1e-15 of libm's: the refinement evaluates
// the lune moments up to 10 times per texel and libm's atan2 was a sixth of its time. One division
// reduces to |x| ≤ tan(π/8): θ = atan(s/c) below π/8, π/4 + atan((s−c)/(s+c)) up to 3π/8, π/2 −
// atan(c/s) above; then atan(x) = x·P(x²), P the degree-10 Chebyshev interpolant of atan(x)/x in x²
// (max error 7e-16 on that interval).
double lune_angle(double s, double c) {
  constexpr double kTan8 = 0.41421356237309503;  // tan(π/8)
  double x, base;
  if (s <= kTan8 * c) x = s / c, base = 0.0;
  else if (c <= kTan8 * s) x = -c / s, base = kPi / 2;
  else x = (s - c) / (s + c), base = kPi / 4;
  const double z = x * x;
  // Estrin's scheme: the Horner chain's eleven dependent multiply-adds were its latency.
  const double z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
  const double q0 = 0.99999999999999956 - 0.33333333333335963 * z, q1 = 0.19999999998321433 - 0.14285714057523832 * z;
  const double q2 = 0.11111099589401892 - 0.090905974241432402 * z, q3 = 0.076872347183822617 - 0.066147664648242871 * z;
  const double q4 = 0.055462667194629479 - 0.039141971734351758 * z;
  const double r0 = q0 + q1 * z2, r1 = q2 + q3 * z2, r2 = q4 + 0.015560176742093798 * z2;
  const double p = (r0 + r1 * z4) + r2 * z8;
  return base + x * p;
}

}  // namespace

HemisphereMoments hemisphere_moments(const IrradiancePoly& poly, const double d[3], bool with_f2) {
  // Rotate about z so that d lies in the xz-plane with d_x ≥ 0 (the hemisphere is invariant).
  const double rxy = std::sqrt(d[0] * d[0] + d[1] * d[1]);
  const double cphi = rxy > 0 ? d[0] / rxy : 1.0, sphi = rxy > 0 ? d[1] / rxy : 0.0;
  const double R[3][3] = {{cphi, sphi, 0}, {-sphi, cphi, 0}, {0, 0, 1}};
  const IrradiancePoly p = rotate_poly(poly, R);
  const double c = std::fmax(-1.0, std::fmin(1.0, d[2]));
  const double s = rxy;
  const double theta = std::atan2(s, c);
  const BetaIntegrals bi(kPi - theta, s, c);

  HemisphereMoments m;
  m.g0 = 2.0 * kPi;
  m.g1 = lune_monomial(bi, s, c, 0, 0, 0, 1);
  m.g2 = lune_monomial(bi, s, c, 0, 0, 0, 2);
  m.f0 = p.e0 * m.g0 + p.e[2] * hemisphere_monomial(0, 0, 1) +
         (p.q[0][0] + p.q[1][1] + p.q[2][2]) * hemisphere_monomial(2, 0, 0);
  // ∫ E g over the lune; y-odd monomials vanish by symmetry.
  m.f1 = p.e0 * m.g1 + p.e[0] * lune_monomial(bi, s, c, 1, 0, 0, 1) +
         p.e[2] * lune_monomial(bi, s, c, 0, 0, 1, 1) +
         p.q[0][0] * lune_monomial(bi, s, c, 2, 0, 0, 1) +
         p.q[1][1] * lune_monomial(bi, s, c, 0, 2, 0, 1) +
         p.q[2][2] * lune_monomial(bi, s, c, 0, 0, 2, 1) +
         2.0 * p.q[0][2] * lune_monomial(bi, s, c, 1, 0, 1, 1);
  m.f2 = with_f2 ? hemisphere_square(p) : 0.0;
  return m;
}

LuneMoments lune_moments(const IrradiancePoly p[3], const double d[3]) {
  LuneMoments m;
  lune_moments(p, &d, 1, &m);
  return m;
}

namespace {

// lune_moments' body; poly(i) gives direction i's three channel polynomials (one texel's for the
// plain batch, each lane's own for lune_moments_lanes): the same arithmetic either way.
template <class Polys>
void lune_moments_impl(const Polys& poly, const double* const* d, int n, LuneMoments* out) {
  // The same lune integrals as hemisphere_moments(), shared by the three channels, each reduced to
  // its closed form for a unit d = (s, 0, c) (B = π − θ the lune's width; s² + c² = 1):
  //   ∫g = π/2 (1+c), ∫g² = 2/3 (B + sc), ∫x g = 2/3 sB, ∫z g = 2/3 (cB + s), ∫y² g = π/8 (1+c),
  //   ∫x² g = 3π/8 (c/3 + c⁴/3 + s² − s⁴/3), ∫z² g = 3π/8 (2c/3 + c² − c⁴/3 + s⁴/3), ∫xz g = π/8 s(1+c)
  // (this runs up to 10 times per texel in the refinement; tests compare it with hemisphere_moments).
  // One stage at a time over the n directions: their square roots, divisions and polynomials are
  // independent, so they overlap in the pipeline instead of waiting on each other's latency.
  for (int i = 0; i < n; ++i) {
    out[i].s = std::sqrt(d[i][0] * d[i][0] + d[i][1] * d[i][1]);
    out[i].c = std::clamp(d[i][2], -1.0, 1.0);
  }
  for (int i = 0; i < n; ++i) {
    const double s = out[i].s, c = out[i].c;
    out[i].B = kPi - (c > 0.0 ? lune_angle(s, c) : std::atan2(s, c));
  }
  // Per channel, in d's own coordinates (no rotation into the lune frame): with u = (cos φ, sin φ)
  // and d_xy = s u, ∫x g·e_x = 2/3 B (e·d_xy); q_xx ∫x² g + q_yy ∫y² g = π/8 d_xyᵀQd_xy + (Q_xx+Q_yy) ∫y² g
  // (q_xx + q_yy is invariant and ∫x² g − ∫y² g = π/8 s²); 2 q_xz ∫xz g = π/4 (1+c)(Q_xz d_x + Q_yz d_y).
  for (int i = 0; i < n; ++i) {
    LuneMoments& m = out[i];
    const double s = m.s, c = m.c, B = m.B;
    const double s4 = s * s * s * s, c4 = c * c * c * c;
    m.g1 = kPi / 2 * (1 + c);
    m.g2 = 2.0 / 3 * (B + s * c);
    const double dx = d[i][0], dy = d[i][1];
    const double lz = 2.0 / 3 * (c * B + s), lyy = kPi / 8 * (1 + c);
    const double lzz = 3 * kPi / 8 * (2 * c / 3 + c * c - c4 / 3 + s4 / 3);
    const double kx = 2.0 / 3 * B, kq = kPi / 8, kxz = kPi / 4 * (1 + c);
    const double dxx = dx * dx, dyy = dy * dy, dxy2 = 2.0 * dx * dy;
    const IrradiancePoly* p = poly(i);
    for (int k = 0; k < 3; ++k) {
      const IrradiancePoly& q = p[k];
      const double ed = q.e[0] * dx + q.e[1] * dy;
      const double qdd = q.q[0][0] * dxx + q.q[0][1] * dxy2 + q.q[1][1] * dyy;
      const double qzd = q.q[0][2] * dx + q.q[1][2] * dy;
      m.f1[k] = q.e0 * m.g1 + kx * ed + q.e[2] * lz + kq * qdd + (q.q[0][0] + q.q[1][1]) * lyy + q.q[2][2] * lzz +
                kxz * qzd;
    }
  }
}

}  // namespace

void lune_moments(const IrradiancePoly p[3], const double* const* d, int n, LuneMoments* out) {
  lune_moments_impl([p](int) { return p; }, d, n, out);
}

void lune_moments_lanes(const IrradiancePoly* const* p, const double* const* d, int n, LuneMoments* out) {
  lune_moments_impl([p](int i) { return p[i]; }, d, n, out);
}

double hemisphere_square_integral(const IrradiancePoly& p) {
  // hemisphere_square's sum as cᵀ G c with the Gram matrix G_ij = ∫_{Ω+} m_i m_j of the ten
  // monomials m = (1, x, y, z, x², y², z², xy, xz, yz), tabulated once: a tenth of the work (the
  // coherence pass calls this per texel). Equal to hemisphere_square up to rounding.
  static const int kExp[10][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 0, 0},
                                  {0, 2, 0}, {0, 0, 2}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}};
  struct Gram {
    double g[10][10];
    Gram() {
      for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j)
          g[i][j] = hemisphere_monomial(kExp[i][0] + kExp[j][0], kExp[i][1] + kExp[j][1], kExp[i][2] + kExp[j][2]);
    }
  };
  static const Gram gram;
  const double c[10] = {p.e0,      p.e[0],    p.e[1],    p.e[2],          p.q[0][0],
                        p.q[1][1], p.q[2][2], 2 * p.q[0][1], 2 * p.q[0][2], 2 * p.q[1][2]};
  // Half of G is 0 (monomials odd in x or y integrate to 0 over Ω+): each row sums only its nonzero
  // entries, in the loop's order (0 + G_i0 c_0 + …), so the sum is the full product's bit for bit
  // (no FMA contraction in this build; for finite c, adding 0·c_j changes nothing), written out:
  // the pass calls this three times a texel and the 100-term loop was a tenth of its time. By
  // monomial: the rows of 1, z, x², y², z² reach {1, z, x², y², z²}; x and xz reach {x, xz}; y and
  // yz {y, yz}; xy {xy}.
  const auto& g = gram.g;
  auto even_row = [&](int i) {
    return 0.0 + g[i][0] * c[0] + g[i][3] * c[3] + g[i][4] * c[4] + g[i][5] * c[5] + g[i][6] * c[6];
  };
  const double r0 = even_row(0), r3 = even_row(3), r4 = even_row(4), r5 = even_row(5), r6 = even_row(6);
  const double r1 = 0.0 + g[1][1] * c[1] + g[1][8] * c[8], r8 = 0.0 + g[8][1] * c[1] + g[8][8] * c[8];
  const double r2 = 0.0 + g[2][2] * c[2] + g[2][9] * c[9], r9 = 0.0 + g[9][2] * c[2] + g[9][9] * c[9];
  const double r7 = 0.0 + g[7][7] * c[7];
  double sum = 0;
  sum += c[0] * r0;
  sum += c[1] * r1;
  sum += c[2] * r2;
  sum += c[3] * r3;
  sum += c[4] * r4;
  sum += c[5] * r5;
  sum += c[6] * r6;
  sum += c[7] * r7;
  sum += c[8] * r8;
  sum += c[9] * r9;
  return sum;
}

double hemisphere_integral(const IrradiancePoly& p) {
  // ∫_{Ω+} 1 = 2π, ∫ z = π, ∫ x² = ∫ y² = ∫ z² = 2π/3 (hemisphere_monomial's values, inlined: the
  // refinement calls this for every texel).
  return 2.0 * kPi * p.e0 + p.e[2] * kPi + (p.q[0][0] + p.q[1][1] + p.q[2][2]) * (2.0 * kPi / 3.0);
}

}  // namespace ahd

// The constrained AHD fit (paper 000 §2–3): closed-form moments and t against brute force,
// constraints on 1e6 random texels, the Figure 2 interpolation case, and the hard cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "fit/ahd_decode.h"
#include "fit/ahd_fit.h"
#include "fit/fit_image.h"
#include "image/sh_exr.h"
#include "lab/hard_cases.h"
#include "sanitized.h"

using namespace ahd;

namespace {

// Random valid SH: 1–4 directional lights anywhere on the sphere plus ambient, random colours,
// over five decades of brightness. L1 or L2.
void random_texel(std::mt19937& rng, int coeffs, float* sh) {
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  std::fill(sh, sh + coeffs * 3, 0.0f);
  const double scale = std::pow(10.0, u(rng) * 5 - 2);
  const int lights = 1 + int(u(rng) * 4);
  for (int l = 0; l < lights; ++l) {
    double d[3] = {g(rng), g(rng), g(rng)};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double& v : d) v /= len;
    const double rgb[3] = {scale * u(rng), scale * u(rng), scale * u(rng)};
    add_directional_light(sh, coeffs, d, rgb);
  }
  const double amb[3] = {scale * 0.1 * u(rng), scale * 0.1 * u(rng), scale * 0.1 * u(rng)};
  add_ambient(sh, amb);
}

void polys_of(const float* sh, int coeffs, IrradiancePoly p[3]) {
  for (int c = 0; c < 3; ++c) p[c] = irradiance_poly(sh + c, coeffs, 3);
}

// Hemisphere quadrature independent of the lune formulas: θ from z, φ around z, Gauss–Legendre
// on pieces split at the kink of max(0, ω·d), so the integrand is smooth on every piece.
struct Quadrature {
  std::vector<double> w, dir;  // weights, directions
};

void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& wt) {
  x.resize(size_t(n));
  wt.resize(size_t(n));
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 0;
    for (int it = 0; it < 100; ++it) {
      double p1 = 1, p2 = 0;
      for (int j = 0; j < n; ++j) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2 * j + 1) * z * p2 - j * p3) / (j + 1);
      }
      pp = n * (z * p1 - p2) / (z * z - 1);
      const double z1 = z;
      z = z1 - p1 / pp;
      if (std::fabs(z - z1) < 1e-15) break;
    }
    x[size_t(i)] = z;
    wt[size_t(i)] = 2 / ((1 - z * z) * pp * pp);
  }
}

Quadrature hemisphere_quadrature(const double d[3]) {
  std::vector<double> gx, gw;
  gauss_legendre(16, gx, gw);
  const double phid = std::atan2(d[1], d[0]);
  std::vector<double> cuts = {0, 2 * kPi};
  for (double c : {phid + kPi / 2, phid - kPi / 2}) {
    c = std::fmod(c + 4 * kPi, 2 * kPi);
    if (c > 0 && c < 2 * kPi) cuts.push_back(c);
  }
  std::sort(cuts.begin(), cuts.end());
  // Near a cut the kink's θ moves fast in φ (over a width ~ d_z): grade the φ subintervals
  // geometrically towards both ends of every piece.
  std::vector<double> phis;
  for (size_t s = 0; s + 1 < cuts.size(); ++s) {
    const double a = cuts[s], b = cuts[s + 1], half = 0.5 * (b - a);
    std::vector<double> pts = {a, b, a + half};
    for (int j = 1; j <= 18; ++j) {
      pts.push_back(a + half * std::ldexp(1.0, -j));
      pts.push_back(b - half * std::ldexp(1.0, -j));
    }
    std::sort(pts.begin(), pts.end());
    for (double p : pts) phis.push_back(p);
  }
  Quadrature q;
  const double rxy = std::hypot(d[0], d[1]);
  for (size_t s = 0; s + 1 < phis.size(); ++s) {
    const double a = phis[s], b = phis[s + 1];
    if (b <= a) continue;
    for (size_t i = 0; i < gx.size(); ++i) {
      const double ph = 0.5 * (a + b) + 0.5 * (b - a) * gx[i];
      const double wph = 0.5 * (b - a) * gw[i];
      // Kink in θ where sinθ·rxy·cos(φ−φd) + cosθ·d_z = 0.
      std::vector<double> tc = {0, kPi / 2};
      const double k = rxy * std::cos(ph - phid);
      const double th = std::atan2(-d[2], k);
      for (double t : {th, th + kPi, th - kPi})
        if (t > 0 && t < kPi / 2) tc.push_back(t);
      std::sort(tc.begin(), tc.end());
      for (size_t r = 0; r + 1 < tc.size(); ++r) {
        const double ta = tc[r], tb = tc[r + 1];
        for (size_t j = 0; j < gx.size(); ++j) {
          const double t = 0.5 * (ta + tb) + 0.5 * (tb - ta) * gx[j];
          const double wt = 0.5 * (tb - ta) * gw[j] * std::sin(t) * wph;
          q.w.push_back(wt);
          q.dir.push_back(std::sin(t) * std::cos(ph));
          q.dir.push_back(std::sin(t) * std::sin(ph));
          q.dir.push_back(std::cos(t));
        }
      }
    }
  }
  return q;
}

}  // namespace

TEST(Fit, MomentsMatchIndependentQuadrature) {
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 60; ++trial) {
    float sh[27];
    random_texel(rng, 9, sh);
    IrradiancePoly p[3];
    polys_of(sh, 9, p);
    double d[3] = {g(rng), g(rng), std::fabs(g(rng)) * (trial % 3 ? 1 : 0.05)};
    if (trial == 0) d[0] = 0, d[1] = 0, d[2] = 1;
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double& v : d) v /= len;
    const HemisphereMoments m = hemisphere_moments(p[0], d);
    const Quadrature q = hemisphere_quadrature(d);
    double g1 = 0, g2 = 0, f0 = 0, f1 = 0, f2 = 0, g0 = 0;
    for (size_t i = 0; i < q.w.size(); ++i) {
      const double* w = &q.dir[i * 3];
      const double gg = std::max(0.0, w[0] * d[0] + w[1] * d[1] + w[2] * d[2]);
      const double e = eval_irradiance(p[0], w);
      g0 += q.w[i], g1 += q.w[i] * gg, g2 += q.w[i] * gg * gg;
      f0 += q.w[i] * e, f1 += q.w[i] * e * gg, f2 += q.w[i] * e * e;
    }
    const double scale = std::fabs(f0) + 1e-30;
    EXPECT_NEAR(m.g0, g0, 1e-10);
    EXPECT_NEAR(m.g1, g1, 1e-10) << "trial " << trial;
    EXPECT_NEAR(m.g2, g2, 1e-10) << "trial " << trial;
    EXPECT_NEAR(m.f0, f0, 1e-10 * scale);
    EXPECT_NEAR(m.f1, f1, 1e-10 * scale) << "trial " << trial;
    EXPECT_NEAR(m.f2, f2, 1e-9 * (std::fabs(f2) + 1e-30));
  }
}

TEST(Fit, ClosedFormTMatchesBruteForceSearch) {
  std::mt19937 rng(2);
  int checked = 0;
  for (int trial = 0; trial < 100; ++trial) {
    float sh[27];
    const int coeffs = trial % 2 ? 9 : 4;
    random_texel(rng, coeffs, sh);
    IrradiancePoly p[3];
    polys_of(sh, coeffs, p);
    FitOptions opt;
    double d[3];
    optimal_direction(p, opt, d);
    tilt_above_horizon(d, opt.dz_min);
    const Quadrature q = hemisphere_quadrature(d);
    std::vector<double> gv(q.w.size()), ev(q.w.size());
    for (int c = 0; c < 3; ++c) {
      const double iz = p[c].e0 + p[c].e[2] + p[c].q[2][2];
      if (iz <= 0) continue;
      for (size_t i = 0; i < q.w.size(); ++i) {
        const double* w = &q.dir[i * 3];
        gv[i] = std::max(0.0, w[0] * d[0] + w[1] * d[1] + w[2] * d[2]);
        ev[i] = eval_irradiance(p[c], w);
      }
      const double dz = d[2], k = 1 / (dz * dz + 1), a0 = iz * k, b0 = iz * dz * k;
      auto E = [&](double t) {
        double s = 0;
        for (size_t i = 0; i < q.w.size(); ++i) {
          const double r = (a0 - dz * t) + (b0 + t) * gv[i] - ev[i];
          s += q.w[i] * r * r;
        }
        return s;
      };
      // Brute force: a grid over [t_min, t_max], then golden-section search around the best cell.
      const double lo = -b0, hi = a0 / dz;
      const int N = 64;
      int best = 0;
      double bestv = E(lo);
      for (int i = 1; i <= N; ++i) {
        const double v = E(lo + (hi - lo) * i / N);
        if (v < bestv) bestv = v, best = i;
      }
      double a = lo + (hi - lo) * std::max(0, best - 1) / N, b = lo + (hi - lo) * std::min(N, best + 1) / N;
      const double gr = (std::sqrt(5.0) - 1) / 2;
      for (int it = 0; it < 200 && b - a > 1e-15 * (std::fabs(a) + std::fabs(b)); ++it) {
        const double x1 = b - gr * (b - a), x2 = a + gr * (b - a);
        if (E(x1) < E(x2)) b = x2; else a = x1;
      }
      const double t_bf = 0.5 * (a + b);
      double ca, cd, t;
      fit_channel(hemisphere_moments(p[c], d), iz, dz, &ca, &cd, &t);
      // Relative to the size of the feasible interval's scale (t itself may be ~0).
      EXPECT_NEAR(t, t_bf, 1e-5 * std::max(std::fabs(t_bf), iz)) << "trial " << trial << " channel " << c;
      ++checked;
    }
  }
  EXPECT_GT(checked, 250);
}

TEST(Fit, MillionRandomTexelsKeepIzAndNonNegativity) {
  std::mt19937 rng(12345);
  FitOptions opt;
  double worst_iz = 0;
  size_t n = 0;
  const long count = ahd_test::sweep_count(1000000);  // a fifth under sanitizers (sanitized.h)
  for (long i = 0; i < count; ++i) {
    float sh[27];
    const int coeffs = i % 2 ? 9 : 4;
    random_texel(rng, coeffs, sh);
    IrradiancePoly p[3];
    polys_of(sh, coeffs, p);
    const AhdFit f = fit_texel(p, opt);
    for (int c = 0; c < 3; ++c) {
      ASSERT_GE(fitted_ca(f, c), 0.0f);
      ASSERT_GE(fitted_cd(f, c), 0.0f);
      ASSERT_TRUE(std::isfinite(fitted_ca(f, c)) && std::isfinite(fitted_cd(f, c)));
      ASSERT_GE(f.ratio[c], 0.0f);
      ASSERT_LE(f.ratio[c], 1.0f);
      const double iz_sh = p[c].e0 + p[c].e[2] + p[c].q[2][2];
      if (iz_sh <= 0) continue;
      // The stored I_z is the SH irradiance along z, and the AHD lobe reproduces it.
      const double back = double(fitted_ca(f, c)) + double(f.d[2]) * fitted_cd(f, c);
      worst_iz = std::max(worst_iz, std::fabs(back - iz_sh) / iz_sh);
      worst_iz = std::max(worst_iz, std::fabs(double(f.iz[c]) - iz_sh) / iz_sh);
      ++n;
    }
    ASSERT_GE(f.d[2], float(opt.dz_min) - 1e-7f);
  }
  EXPECT_LE(worst_iz, 1e-6);
  EXPECT_GT(n, size_t(count) * 5 / 2);
  std::printf("worst relative I_z error over %zu channels: %.3g\n", n, worst_iz);
}

TEST(Fit, ConstrainedFitIsNeverWorseThanEndpointsAndBeatsPseudoInverse) {
  // The minimiser must beat (or tie) the pseudo-inverse point and both feasible endpoints.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 2000; ++trial) {
    float sh[27];
    random_texel(rng, 9, sh);
    IrradiancePoly p[3];
    polys_of(sh, 9, p);
    FitOptions opt;
    double d[3];
    optimal_direction(p, opt, d);
    tilt_above_horizon(d, opt.dz_min);
    const double iz = p[0].e0 + p[0].e[2] + p[0].q[2][2];
    if (iz <= 0) continue;
    const HemisphereMoments m = hemisphere_moments(p[0], d);
    double ca, cd;
    fit_channel(m, iz, d[2], &ca, &cd);
    const double e = hemisphere_mse(m, ca, cd);
    const double k = 1 / (d[2] * d[2] + 1);
    EXPECT_LE(e, hemisphere_mse(m, iz, 0) * (1 + 1e-9) + 1e-12);
    EXPECT_LE(e, hemisphere_mse(m, 0, iz / d[2]) * (1 + 1e-9) + 1e-12);
    EXPECT_LE(e, hemisphere_mse(m, iz * k, iz * d[2] * k) * (1 + 1e-9) + 1e-12);
  }
}

TEST(Fit, Figure2NaiveInterpolationOvershootsOursIsLinear) {
  // Texel A: a unit directional light tilted far to the left; texel B: zero intensity, tilted right.
  const double s = std::sin(80 * kPi / 180), c = std::cos(80 * kPi / 180);
  const double dA[3] = {-s, 0, c}, dB[3] = {s, 0, c};
  ShImage img = make_sh_image(2, 1, 9);
  const double one[3] = {1, 1, 1}, tiny[3] = {1e-6, 1e-6, 1e-6};
  add_directional_light(img.texel(0), 9, dA, one);
  add_directional_light(img.texel(1), 9, dB, tiny);
  FitOptions opt;
  const AhdImage fit = fit_image(img, opt, 1);
  const AhdFit A = fit.texel(0), B = fit.texel(1);
  double naive_overshoot = 0, ours_dev = 0;
  for (int k = 0; k <= 64; ++k) {
    const double t = k / 64.0;
    const double iz_lin = (1 - t) * A.iz[0] + t * B.iz[0];
    // Naive: interpolate (C_a, d, C_d), renormalise d.
    double d[3];
    for (int i = 0; i < 3; ++i) d[i] = (1 - t) * A.d[i] + t * B.d[i];
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double ca = (1 - t) * fitted_ca(A, 0) + t * fitted_ca(B, 0), cd = (1 - t) * fitted_cd(A, 0) + t * fitted_cd(B, 0);
    const double naive = ca + std::max(0.0, d[2] / len) * cd;
    naive_overshoot = std::max(naive_overshoot, naive - iz_lin);
    // Ours: interpolate (I_z, d, ratio), decode.
    float iz[3], df[3], r[3];
    for (int i = 0; i < 3; ++i) {
      iz[i] = float((1 - t) * A.iz[i] + t * B.iz[i]);
      df[i] = float((1 - t) * A.d[i] + t * B.d[i]);
      r[i] = float((1 - t) * A.ratio[i] + t * B.ratio[i]);
    }
    const double z[3] = {0, 0, 1};
    double out[3];
    decode_irradiance(iz, df, r, z, opt.dz_min, out);
    ours_dev = std::max(ours_dev, std::fabs(out[0] - iz_lin) / A.iz[0]);
  }
  EXPECT_GT(naive_overshoot, 0.5 * A.iz[0]) << "the naive parameterization should over-shoot";
  EXPECT_LT(ours_dev, 1e-6);
  std::printf("Figure 2: naive over-shoot %.3f × I_z(A); ours max deviation %.2g\n", naive_overshoot / A.iz[0], ours_dev);
}

TEST(Fit, HardCasesStayFiniteAndConstrained) {
  FitOptions opt;
  for (HardCase& hc : hard_cases()) {
    ReadStats rs;
    sanitise_sh(hc.sh, false, &rs);
    FitStats st;
    const AhdImage fit = fit_image(hc.sh, opt, 1, &st);
    for (size_t i = 0; i < fit.size(); ++i) {
      const AhdFit f = fit.texel(i);
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(f.iz[c]) && std::isfinite(fitted_ca(f, c)) && std::isfinite(fitted_cd(f, c))) << hc.name;
        ASSERT_GE(f.iz[c], 0.0f) << hc.name;
        ASSERT_GE(fitted_ca(f, c), 0.0f) << hc.name;
        ASSERT_GE(fitted_cd(f, c), 0.0f) << hc.name;
        ASSERT_LE(fitted_cd(f, c), f.iz[c] / opt.dz_min * (1 + 1e-6) + 1e-30) << hc.name << ": C_d bound";
        ASSERT_GE(f.ratio[c], 0.0f);
        ASSERT_LE(f.ratio[c], 1.0f);
        ASSERT_NEAR(fitted_ca(f, c) + f.d[2] * fitted_cd(f, c), f.iz[c], 1e-6 * f.iz[c] + 1e-37) << hc.name;
      }
      ASSERT_GE(f.d[2], float(opt.dz_min) - 1e-7f) << hc.name;
      ASSERT_NEAR(f.d[0] * f.d[0] + f.d[1] * f.d[1] + f.d[2] * f.d[2], 1.0f, 1e-5f) << hc.name;
    }
    if (hc.name.rfind("NaN", 0) == 0) {
      EXPECT_EQ(rs.non_finite_texels, 3u) << "NaN, +Inf and −Inf texels are counted";
    }
    if (hc.name.rfind("black", 0) == 0) {
      EXPECT_EQ(st.black, fit.size());
    }
    if (hc.name.rfind("pure ambient", 0) == 0) {
      EXPECT_EQ(st.no_direction, fit.size());
    }
    if (hc.name.rfind("negative SH", 0) == 0) {
      EXPECT_GE(st.negative_iz, 1u);
    }
    if (hc.name.rfind("directional light swept", 0) == 0) {
      EXPECT_GE(st.dir_clamped, 6u);
    }
    if (hc.name.rfind("two opposed", 0) == 0) {
      // Lights at ±x cancel L1 exactly: no preferred direction.
      EXPECT_TRUE(fit.texel(1).flags & kFitNoDirection);
    }
  }
}

TEST(Fit, PureAmbientIsAllAmbient) {
  ShImage img = make_sh_image(1, 1, 9);
  const double a[3] = {0.2, 0.4, 0.6};
  add_ambient(img.texel(0), a);
  const AhdImage fit = fit_image(img, FitOptions{}, 1);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(fitted_ca(fit.texel(0), c), fit.texel(0).iz[c], 1e-6 * fit.texel(0).iz[c]);
    EXPECT_NEAR(fitted_cd(fit.texel(0), c), 0.0f, 1e-6 * fit.texel(0).iz[c]);
    EXPECT_NEAR(fit.texel(0).iz[c], kPi * a[c], 1e-5);  // constant radiance L gives E = πL
  }
}

TEST(Fit, WorldSpaceInputEqualsTangentSpaceInput) {
  // The same lighting given in world space with a normal must fit like its tangent-space form.
  std::mt19937 rng(9);
  ShImage tangent = make_sh_image(1, 1, 9);
  random_texel(rng, 9, tangent.texel(0));
  const double n[3] = {0.48, 0.6, 0.64};
  double R[3][3];
  frame_from_normal(n, R);
  // World SH: rotate the lights. Rebuild from a light set instead of rotating SH coefficients.
  ShImage t2 = make_sh_image(1, 1, 9), world = make_sh_image(1, 1, 9);
  const double dl[2][3] = {{0.3, 0.1, 0.948683}, {-0.7, 0.5, 0.509902}};
  const double col[2][3] = {{1, 0.5, 0.2}, {0.1, 0.2, 0.9}};
  for (int l = 0; l < 2; ++l) {
    add_directional_light(t2.texel(0), 9, dl[l], col[l]);
    double w[3];  // local → world: w = Rᵀ local
    for (int i = 0; i < 3; ++i) w[i] = R[0][i] * dl[l][0] + R[1][i] * dl[l][1] + R[2][i] * dl[l][2];
    add_directional_light(world.texel(0), 9, w, col[l]);
  }
  world.normals = {float(n[0]), float(n[1]), float(n[2])};
  const AhdFit a = fit_image(t2, FitOptions{}, 1).texel(0);
  const AhdFit b = fit_image(world, FitOptions{}, 1).texel(0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(a.iz[c], b.iz[c], 1e-5 * a.iz[c]);
    EXPECT_NEAR(a.d[c], b.d[c], 1e-5);
    EXPECT_NEAR(a.ratio[c], b.ratio[c], 1e-5);
  }
}

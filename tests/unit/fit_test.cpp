// The constrained AHD fit (paper 000 §2–3): moments against quadrature, the Figure 2 interpolation
// case, the hard cases. t against brute force and 10⁶ random texels: tests/accuracy/fit_test.cpp.
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
#include "fit_fixture.h"

using namespace ahd;
using namespace ahd_fixture::fit_fixture;

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

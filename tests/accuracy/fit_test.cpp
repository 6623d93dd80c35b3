// The constrained fit over many inputs: the closed-form t against a brute-force search, and I_z
// exact with non-negative colours on 10⁶ random texels. Unit tests: tests/unit/fit_test.cpp.
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

// Issue 18's refined fit measured over many inputs: error ratios against the unconstrained LS fit on
// random lighting and on the analytic scene, coherence and the pair guard, never worse than the
// paper's choice, constraints on 10⁶ random texels, filtered error, and the window on a noisy scene.
// The refined fit's unit tests: tests/unit/fit_refine_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <vector>

#include "fit_bits.h"
#include "fit_refine_fixture.h"
#include "sanitized.h"
#include "fit/ahd_decode.h"
#include "fit/direction_filter.h"
#include "fit/direction_guard.h"
#include "fit/direction_refine.h"
#include "fit/fit_image.h"
#include "lab/fit_quality.h"
#include "fit/refine_objective.h"
#include "image/ahd_intermediate.h"
#include "image/sh_exr.h"
#include "sample/analytic_baker.h"
#include "lab/hard_cases.h"

using namespace ahd;
using namespace ahd::fit_refine_fixture;

TEST(FitRefine, ErrorRatiosAgainstUnconstrainedLeastSquares) {
  // Mean over texels of the hemisphere RMS error (exact integrals) / the same for the LS fit at the
  // linear d. Sets 0, 1: issue 18's calibrated sets, where the linear fit reproduces the issue's
  // "today" (random 1.31 / 1.57, smooth 1.03 / 1.05; asserted, so that the calibration cannot
  // drift) and the refined fit is bounded by the issue's targets (measured: random 0.992 / 1.178,
  // smooth 0.999 / 1.014 with the pair guard). Sets 2, 3: the harder sets (independent light
  // colours, the canonical scene 64²), measured 0.980 / 1.288 and, with the pair guard (which
  // reverts 11 % / 10 % of the scene's texels to the linear fit), 1.087 / 1.115; bounded 1–2 % above.
  const ShImage sets[4] = {calibrated_random_set(20000, 7), calibrated_smooth_scene(), random_lighting_set(20000, 7),
                           smooth_scene()};
  const double today[2][2] = {{1.31, 1.57}, {1.03, 1.05}};
  const double bound[4][2] = {{1.05, 1.20}, {1.00, 1.02}, {0.996, 1.304}, {1.098, 1.126}};  // [set][rgb, luminance]
  const double gain[4] = {0.78, 0.98, 0.78, 0.97};                                          // refined / linear at most
  for (int s = 0; s < 4; ++s)
    for (int f = 0; f < 2; ++f) {
      const RatioForm form = f ? RatioForm::Luminance : RatioForm::Rgb;
      const FitOptions lin = options(form, DirectionFit::Linear), ref = options(form, DirectionFit::Refined);
      const FitQuality ql = fit_quality(sets[s], fit_image(sets[s], lin, 2), lin, 2);
      const FitQuality qr = fit_quality(sets[s], fit_image(sets[s], ref, 2), ref, 2);
      std::printf("set %d %s: linear %.4f refined %.4f\n", s, f ? "luminance" : "rgb", ql.ratio(), qr.ratio());
      if (s < 2) EXPECT_NEAR(ql.ratio(), today[s][f], 0.01) << "set " << s << " form " << f;
      EXPECT_LE(qr.ratio(), bound[s][f]) << "set " << s << " form " << f;
      EXPECT_LE(qr.ratio(), gain[s] * ql.ratio()) << "set " << s << " form " << f;
    }
}

TEST(FitRefine, CoherencePassIsDeterministicAndHelpsTheSmoothScene) {
  // The neighbour pass reads only the first pass's output: the same bytes for 1 and 3 threads. On
  // the calibrated smooth scene 64² it lowers the neighbour-angle p99 (measured: linear 4.64°,
  // refined without the pass 3.85° / 3.78°, with it and the pair guard 3.70° / 3.44°, RGB /
  // luminance; with the pass alone 3.16° / 3.35°) at no cost in error (0.999 / 1.014 either way).
  const ShImage sh = calibrated_smooth_scene();
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
    const FitOptions lin = options(form, DirectionFit::Linear), ref = options(form, DirectionFit::Refined);
    FitOptions off = ref;
    off.coherence_tolerance = 0;
    const AhdImage a = fit_image(sh, ref, 1), b = fit_image(sh, ref, 3), c = fit_image(sh, off, 2);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
      ASSERT_TRUE(same_fit_bits(a.texel(i), b.texel(i))) << "texel " << i;
    const double p_lin = direction_p99_angle_deg(fit_image(sh, lin, 2));
    const double p_off = direction_p99_angle_deg(c), p_on = direction_p99_angle_deg(a);
    const double e_off = fit_quality(sh, c, ref, 2).ratio(), e_on = fit_quality(sh, a, ref, 2).ratio();
    std::printf("%s: neighbour angle p99 linear %.2f, refined %.2f, + coherence pass %.2f deg; error %.4f -> %.4f\n",
                form == RatioForm::Rgb ? "rgb" : "luminance", p_lin, p_off, p_on, e_off, e_on);
    EXPECT_LT(p_on, p_off);
    EXPECT_LE(p_on, p_lin);
    EXPECT_LE(e_on, e_off * 1.002);
  }
}

TEST(FitRefine, PairGuardBoundsEveryNeighbourAngleByTheLinearOnes) {
  // direction_guard.h on the canonical scene 64² (where the refined field alone turns faster than
  // the linear one: p99 16.95° / 16.23° vs 14.14°): after the guard every pair of adjacent covered
  // texels turns by at most max(T, its linear angle), so the p99 is at most the linear one; every
  // reverted texel is the linear fit's texel byte for byte; the same bytes on 1 and 3 threads.
  const ShImage sh = smooth_scene();
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
    const FitOptions lin = options(form, DirectionFit::Linear), ref = options(form, DirectionFit::Refined);
    FitOptions off = ref;
    off.pair_guard_deg = 0;
    FitStats st;
    const AhdImage a = fit_image(sh, ref, 1, &st), b = fit_image(sh, ref, 3), u = fit_image(sh, off, 2);
    const AhdImage l = fit_image(sh, lin, 2);
    const size_t w = size_t(sh.width), n = sh.texels();
    size_t pairs = 0, bounded_by_linear = 0, reverted = 0;
    for (size_t i = 0; i < n; ++i) {
      ASSERT_TRUE(same_fit_bits(a.texel(i), b.texel(i))) << "texel " << i;
      const bool changed = !same_fit_bits(a.texel(i), u.texel(i));
      if (changed) {
        ++reverted;
        ASSERT_TRUE(same_fit_bits(a.texel(i), l.texel(i))) << "texel " << i;
      }
      for (size_t j : {i + 1, i + w}) {
        if ((j == i + 1 && (i + 1) % w == 0) || j >= n || !sh.coverage[i] || !sh.coverage[j]) continue;
        const double ag = neighbour_angle_deg(&a.d[i * 3], &a.d[j * 3]);
        const double al = neighbour_angle_deg(&l.d[i * 3], &l.d[j * 3]);
        ++pairs;
        bounded_by_linear += ag > ref.pair_guard_deg;
        ASSERT_LE(ag, std::max(ref.pair_guard_deg, al)) << "pair " << i << ", " << j;
      }
    }
    const double p_lin = direction_p99_angle_deg(l), p_off = direction_p99_angle_deg(u);
    const double p_on = direction_p99_angle_deg(a);
    std::printf("%s: p99 linear %.2f, refined %.2f, guarded %.2f deg; %zu of %zu covered texels reverted; "
                "error %.4f -> %.4f (linear %.4f)\n",
                form == RatioForm::Rgb ? "rgb" : "luminance", p_lin, p_off, p_on, reverted, st.covered,
                fit_quality(sh, u, ref, 2).ratio(), fit_quality(sh, a, ref, 2).ratio(), fit_quality(sh, l, lin, 2).ratio());
    EXPECT_GT(pairs, 7000u);
    EXPECT_GT(bounded_by_linear, 0u);  // pairs above T exist: the linear angle is what bounds them
    EXPECT_GT(p_off, p_lin);           // the guard had something to do
    EXPECT_LE(p_on, std::max(ref.pair_guard_deg, p_lin));
    EXPECT_GT(reverted, 0u);
    EXPECT_EQ(reverted <= st.guard_reverted, true);  // reverted texels already linear do not show as changed
    // The linear d the guard compares against, as fit_texel hands it on: linear_direction's, and the
    // d the linear fit stores.
    for (size_t i = 0; i < n; ++i) {
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      float handed[3], direct[3];
      fit_texel(p, ref, handed);
      linear_direction(p, ref, direct);
      ASSERT_EQ(std::memcmp(handed, direct, sizeof handed), 0) << "texel " << i;
      ASSERT_EQ(std::memcmp(handed, &l.d[i * 3], sizeof handed), 0) << "texel " << i;
    }
  }
}

TEST(FitRefine, IssueMeasureSampledDirections) {
  // Issue 18's measure as it states it: 400 sampled directions, fitted float planes against the
  // unconstrained LS AHD at the linear d. Sampling (uniform in solid angle) agrees with the exact
  // integrals, so the ratio of means equals the exact ratio; the mean of per-texel ratios weighs
  // dim texels as much as bright ones. Measured on random lighting, RGB: ratio of means 1.283 →
  // 0.980, mean of texel ratios 1.278 → 1.033; target ≤ 1.05 for both.
  const ShImage sh = random_lighting_set(20000, 7);
  const FitOptions lin = options(RatioForm::Rgb, DirectionFit::Linear), ref = options(RatioForm::Rgb, DirectionFit::Refined);
  const FitQuality ql = fit_quality(sh, fit_image(sh, lin, 2), lin, 2, 400);
  const FitQuality qr = fit_quality(sh, fit_image(sh, ref, 2), ref, 2, 400);
  std::printf("rgb, 400 directions: ratio of means %.4f -> %.4f, mean of texel ratios %.4f -> %.4f\n",
              ql.sampled_ratio, qr.sampled_ratio, ql.sampled_texel_ratio, qr.sampled_texel_ratio);
  EXPECT_EQ(qr.directions, 400);
  EXPECT_NEAR(ql.sampled_ratio, ql.ratio(), 0.005);
  EXPECT_NEAR(qr.sampled_ratio, qr.ratio(), 0.005);
  EXPECT_LE(qr.sampled_ratio, 1.05);
  EXPECT_LE(qr.sampled_texel_ratio, 1.05);
  EXPECT_GT(ql.sampled_texel_ratio, 1.2);  // the measure does see what the linear d costs
}

TEST(FitRefine, NeverWorseThanTheLinearDirectionPerTexel) {
  const ShImage sh = random_lighting_set(20000, 11);
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
    const FitOptions lin = options(form, DirectionFit::Linear), ref = options(form, DirectionFit::Refined);
    int moved = 0;
    for (size_t i = 0; i < sh.texels(); ++i) {
      IrradiancePoly p[3];
      double iz[3];
      polys_and_iz(sh, i, p, iz);
      const AhdFit a = fit_texel(p, lin), b = fit_texel(p, ref);
      const double da[3] = {a.d[0], a.d[1], a.d[2]}, db[3] = {b.d[0], b.d[1], b.d[2]};
      const double ea = constrained_error(p, iz, da, ref), eb = constrained_error(p, iz, db, ref);
      const double scale = 2 * kPi * (iz[0] * iz[0] + iz[1] * iz[1] + iz[2] * iz[2]) + 1e-300;
      ASSERT_LE(eb, ea + 1e-6 * scale) << "texel " << i;
      moved += eb < ea - 1e-6 * scale;
    }
    EXPECT_GT(moved, 10000) << "the refinement should move most texels of random lighting";
  }
}

TEST(FitRefine, MillionRandomTexelsKeepIzAndNonNegativity) {
  const int n = int(ahd_test::sweep_count(1000000));  // a fifth under sanitizers (sanitized.h)
  const ShImage sh = random_lighting_set(n, 12345);
  double worst_iz = 0;
  size_t checked = 0;
  for (int i = 0; i < n; ++i) {
    const FitOptions opt = options(i % 2 ? RatioForm::Luminance : RatioForm::Rgb, DirectionFit::Refined);
    IrradiancePoly p[3];
    double iz[3];
    polys_and_iz(sh, size_t(i), p, iz);
    const AhdFit f = fit_texel(p, opt);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(fitted_ca(f, c)) && std::isfinite(fitted_cd(f, c)));
      ASSERT_GE(fitted_ca(f, c), 0.0f);
      ASSERT_GE(fitted_cd(f, c), 0.0f);
      ASSERT_GE(f.ratio[c], 0.0f);
      ASSERT_LE(f.ratio[c], 1.0f);
      if (!(iz[c] > 0)) continue;
      const double back = double(fitted_ca(f, c)) + double(f.d[2]) * fitted_cd(f, c);
      worst_iz = std::max(worst_iz, std::fabs(back - iz[c]) / iz[c]);
      worst_iz = std::max(worst_iz, std::fabs(double(f.iz[c]) - iz[c]) / iz[c]);
      ++checked;
    }
    ASSERT_GE(f.d[2], float(opt.dz_min) - 1e-7f);
  }
  EXPECT_LE(worst_iz, 1e-6);
  EXPECT_GT(checked, size_t(n) * 5 / 2);
  std::printf("refined: worst relative I_z error over %zu channels: %.3g\n", checked, worst_iz);
}

TEST(FitRefine, FilteredErrorOnTheAnalyticSceneIsNoWorse) {
  // Measured on 64²: bilinear sub-texel error relative to the mean irradiance, linear → refined
  // (with the pair guard): RGB 0.1003 → 0.0964, luminance 0.1028 → 0.0988 (without the guard 0.0959
  // / 0.0983). The neighbour-angle p99 is the linear one, 14.14°, with the guard (without it 17.0° /
  // 16.2°): printed here, in docs/fit.md "Choosing the direction beyond the paper".
  const ShImage sh = smooth_scene();
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
    const FitOptions lin = options(form, DirectionFit::Linear), ref = options(form, DirectionFit::Refined);
    const AhdImage a = fit_image(sh, lin, 2), b = fit_image(sh, ref, 2);
    const FilteredError ea = filtered_error(sh, a, lin), eb = filtered_error(sh, b, ref);
    ASSERT_GT(ea.samples, 1000u);
    std::printf("%s: filtered rel linear %.4f refined %.4f; neighbour angle p99 %.2f -> %.2f deg\n",
                form == RatioForm::Rgb ? "rgb" : "luminance", ea.rms / ea.mean_irradiance,
                eb.rms / eb.mean_irradiance, direction_p99_angle_deg(a), direction_p99_angle_deg(b));
    EXPECT_LE(eb.rms, ea.rms);
  }
}

TEST(FitWindow, NoisySceneTurnsSlowerAndFitsTheNoiseFreeSceneBetter) {
  // On a noisy copy of the smooth scene the window's d follows the light, not the noise: the
  // neighbour-angle p99 is far below the per-texel fits', and the fit is closer to the noise-free
  // scene's SH than the linear fit of the noisy SH (measured: p99 linear 27.6, per-texel refined
  // 27.5, windowed 7.3 deg; error vs the clean SH 1.131 / 1.125 / 1.093 of the clean LS, RGB).
  const ShImage clean = calibrated_smooth_scene(), noisy = noisy_scene();
  FitOptions win = options(RatioForm::Rgb, DirectionFit::Refined);
  win.direction_window = 1;
  const AhdImage l = fit_image(noisy, options(RatioForm::Rgb, DirectionFit::Linear), 2);
  const AhdImage r = fit_image(noisy, options(RatioForm::Rgb, DirectionFit::Refined), 2);
  const AhdImage a = fit_image(noisy, win, 2);
  const double pl = direction_p99_angle_deg(l), pr = direction_p99_angle_deg(r), pa = direction_p99_angle_deg(a);
  const double el = fit_quality(clean, l, win, 2).ratio(), er = fit_quality(clean, r, win, 2).ratio();
  const double ea = fit_quality(clean, a, win, 2).ratio();
  std::printf("noisy smooth scene: p99 linear %.2f, refined %.2f, windowed %.2f deg; error vs clean %.4f / %.4f / %.4f\n",
              pl, pr, pa, el, er, ea);
  EXPECT_LT(pa, 0.5 * pl);
  EXPECT_LT(ea, el);
  EXPECT_LT(ea, er);
}

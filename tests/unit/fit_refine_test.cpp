// Issue 18: the refined direction and the least-squares luminance ratio. Error ratios against the
// unconstrained LS fit on random lighting and on the analytic scene, constraints on 10⁶ random
// texels, never worse than the paper's choice, the ratio against brute force, the closed-loop
// refit, coherence under bilinear filtering, hard cases, and the intermediate's record of it.
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

namespace {

// Issue 18's refined fit, each texel's d chosen on its own SH (direction_window 0): what these tests
// pin down. The windowed fit (issue 27) has its own tests at the end.
FitOptions options(RatioForm form, DirectionFit dir) {
  FitOptions o;
  o.ratio_form = form;
  o.direction_fit = dir;
  o.direction_window = 0;
  return o;
}

// The canonical analytic scene (the harder scene of the first round).
ShImage smooth_scene() {
  BakerOptions bo;
  bo.width = bo.height = 64;
  return bake_analytic_scene(bo);
}

// Issue 18's "smooth scene", calibrated to its "today" column (fit_quality.h).
ShImage calibrated_smooth_scene() {
  BakerOptions bo;
  bo.width = bo.height = 64;
  bo.coeffs = kSmoothCoeffs;
  bo.point_scale = kSmoothPointScale, bo.sky_scale = kSmoothSkyScale;
  bo.ceiling_scale = kSmoothCeilingScale, bo.bounce_scale = kSmoothBounceScale;
  return bake_analytic_scene(bo);
}

ShImage calibrated_random_set(int n, uint32_t seed) {
  return random_lighting_set(n, seed, kCalibratedSaturation, kCalibratedAmbient);
}

void polys_and_iz(const ShImage& sh, size_t i, IrradiancePoly p[3], double iz[3]) {
  local_polys(sh, i, p);
  for (int c = 0; c < 3; ++c) iz[c] = std::max(0.0, p[c].e0 + p[c].e[2] + p[c].q[2][2]);
}

}  // namespace

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

TEST(FitRefine, AnalyticGradientMatchesFiniteDifferences) {
  // refine_objective.h's gradient (envelope theorem over the lune) against central differences of
  // the objective along the two tangents, both ratio forms, at several directions.
  const ShImage sh = random_lighting_set(300, 3);
  const double dirs[3][3] = {{0.3, -0.4, 0.8660254037844386}, {-0.8, 0.1, 0.5916079783099616}, {0.0, 0.2, 0.9797958971132712}};
  double worst = 0;
  for (int form = 0; form < 2; ++form)
    for (size_t i = 0; i < sh.texels(); ++i)
      for (const auto& d : dirs) {
        IrradiancePoly p[3];
        double iz[3];
        polys_and_iz(sh, i, p, iz);
        const RefineObjective f(p, iz, form ? RatioForm::Luminance : RatioForm::Rgb);
        double g[3], R[3][3];
        const double fd0 = f.value_grad(d, g);
        frame_from_normal(d, R);
        for (int k = 0; k < 2; ++k) {
          const double h = 1e-6;
          double dp[3], dm[3];
          for (int j = 0; j < 3; ++j) dp[j] = d[j] + h * R[k][j], dm[j] = d[j] - h * R[k][j];
          const double lp = std::sqrt(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2]);
          const double lm = std::sqrt(dm[0] * dm[0] + dm[1] * dm[1] + dm[2] * dm[2]);
          for (int j = 0; j < 3; ++j) dp[j] /= lp, dm[j] /= lm;
          const double fd = (f.value(dp) - f.value(dm)) / (2 * h);
          const double an = g[0] * R[k][0] + g[1] * R[k][1] + g[2] * R[k][2];
          worst = std::max(worst, std::fabs(fd - an) / (std::fabs(fd) + 1e-6 * std::fabs(fd0)));
        }
        ASSERT_NEAR(g[0] * d[0] + g[1] * d[1] + g[2] * d[2], 0.0, 1e-9 * (std::fabs(fd0) + 1e-30));  // tangent
      }
  std::printf("analytic gradient vs central differences: worst relative difference %.3g\n", worst);
  EXPECT_LT(worst, 2e-3);  // measured 2e-4 (the differences' own error)
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

TEST(FitRefine, LeastSquaresRatioBeatsEveryOtherRatio) {
  std::mt19937 rng(3);
  const ShImage sh = random_lighting_set(300, 5);
  for (size_t i = 0; i < sh.texels(); ++i) {
    IrradiancePoly p[3];
    double iz[3], d[3];
    polys_and_iz(sh, i, p, iz);
    optimal_direction(p, FitOptions{}, d);
    tilt_above_horizon(d, 0.05);
    HemisphereMoments m[3];
    for (int c = 0; c < 3; ++c) m[c] = hemisphere_moments(p[c], d);
    auto err = [&](double r) {
      double e = 0;
      for (int c = 0; c < 3; ++c) e += hemisphere_mse(m[c], r * iz[c], (1 - r) * iz[c] / d[2]);
      return e;
    };
    const double f0[3] = {m[0].f0, m[1].f0, m[2].f0};
    const LuneMoments lm{m[0].g1, m[0].g2, {m[0].f1, m[1].f1, m[2].f1}};
    const double r = least_squares_ratio(lm, f0, iz, d[2]);
    ASSERT_GE(r, 0.0);
    ASSERT_LE(r, 1.0);
    const double er = err(r);
    for (int k = 0; k <= 1000; ++k) ASSERT_LE(er, err(k / 1000.0) * (1 + 1e-9) + 1e-300) << "texel " << i << " r " << r;
    // The fused three-channel moments equal the per-channel ones.
    const LuneMoments fused = lune_moments(p, d);
    EXPECT_NEAR(fused.g1, m[0].g1, 1e-12);
    EXPECT_NEAR(fused.g2, m[0].g2, 1e-12);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(fused.f1[c], m[c].f1, 1e-10 * (std::fabs(m[c].f0) + 1e-30));
      EXPECT_NEAR(hemisphere_integral(p[c]), m[c].f0, 1e-10 * (std::fabs(m[c].f0) + 1e-30));
    }
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

TEST(FitRefine, ClosedLoopRefitAtTheStoredPlanesGivesTheSameRatio) {
  // The quantiser refits the ratio with fit_colours at the decoded d and I_z; with no quantisation
  // it must give back the fitted ratio, so the closed loop follows the same rule.
  const ShImage sh = random_lighting_set(5000, 21);
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
    const FitOptions opt = options(form, DirectionFit::Refined);
    for (size_t i = 0; i < sh.texels(); ++i) {
      IrradiancePoly p[3];
      double iz[3];
      polys_and_iz(sh, i, p, iz);
      const AhdFit f = fit_texel(p, opt);
      double d[3] = {f.d[0], f.d[1], f.d[2]};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double& v : d) v /= len;
      tilt_above_horizon(d, opt.dz_min);
      const double izf[3] = {f.iz[0], f.iz[1], f.iz[2]};
      const AhdFit g = fit_colours(p, d, izf, opt);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(g.ratio[c], f.ratio[c], 2e-5) << "texel " << i;
    }
  }
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

TEST(FitRefine, HardCasesStayFiniteAndConstrained) {
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
    const FitOptions opt = options(form, DirectionFit::Refined);
    for (HardCase& hc : hard_cases()) {
      ReadStats rs;
      sanitise_sh(hc.sh, false, &rs);
      const AhdImage fit = fit_image(hc.sh, opt, 1);
      for (size_t i = 0; i < fit.size(); ++i) {
        const AhdFit f = fit.texel(i);
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::isfinite(f.iz[c]) && std::isfinite(fitted_ca(f, c)) && std::isfinite(fitted_cd(f, c))) << hc.name;
          ASSERT_GE(fitted_ca(f, c), 0.0f) << hc.name;
          ASSERT_GE(fitted_cd(f, c), 0.0f) << hc.name;
          ASSERT_LE(fitted_cd(f, c), f.iz[c] / opt.dz_min * (1 + 1e-6) + 1e-30) << hc.name;
          ASSERT_NEAR(fitted_ca(f, c) + f.d[2] * fitted_cd(f, c), f.iz[c], 1e-6 * f.iz[c] + 1e-37) << hc.name;
        }
        ASSERT_GE(f.d[2], float(opt.dz_min) - 1e-7f) << hc.name;
      }
    }
  }
}

TEST(FitRefine, IntermediateRecordsTheDirectionFit) {
  // A transcode refits the ratio closed loop: it must know which rule made the planes.
  const std::string path = (std::filesystem::temp_directory_path() / "ahd_fit_refine_test.ahd.exr").string();
  for (DirectionFit dir : {DirectionFit::Linear, DirectionFit::Refined}) {
    FittedLevel lv;
    lv.sh = random_lighting_set(4, 1);
    const FitOptions opt = options(RatioForm::Luminance, dir);
    lv.ahd = fit_image(lv.sh, opt, 1);
    write_intermediate(path, {lv}, opt);
    FitOptions back = options(RatioForm::Rgb, dir == DirectionFit::Linear ? DirectionFit::Refined : DirectionFit::Linear);
    read_intermediate(path, &back);
    EXPECT_EQ(back.direction_fit, dir);
  }
  std::filesystem::remove(path);
}

TEST(FitRefine, LuneWidthMatchesLibmAtan2) {
  // lune_moments' B = π − atan2(s, d_z) is a polynomial form for d_z > 0 (three octant branches):
  // within 1e-14 of libm's on a dense sweep of the polar angle, including the branch edges π/8 and
  // 3π/8, grazing and zenith; and it keeps the libm value below the horizon.
  IrradiancePoly p[3] = {};
  double worst = 0;
  const double edges[] = {kPi / 8, 3 * kPi / 8};
  std::vector<double> thetas;
  for (int i = 0; i <= 20000; ++i) thetas.push_back(0.5 * kPi * i / 20000 * (1 - 1e-12));
  for (double e : edges)
    for (double k : {-1e-15, 0.0, 1e-15}) thetas.push_back(e + k);
  for (double th : thetas) {
    const double d[3] = {std::sin(th) * 0.6, std::sin(th) * 0.8, std::cos(th)};
    const LuneMoments m = lune_moments(p, d);
    const double s = std::sqrt(d[0] * d[0] + d[1] * d[1]);
    worst = std::max(worst, std::fabs(m.B - (kPi - std::atan2(s, d[2]))));
  }
  std::printf("lune width vs libm atan2: worst %.3g\n", worst);
  EXPECT_LT(worst, 1e-14);
  const double below[3] = {0.8, 0.0, -0.6};
  EXPECT_EQ(lune_moments(p, below).B, kPi - std::atan2(0.8, -0.6));
}

TEST(FitRefine, BatchedStartsGiveTheSameBytesAsSingleEvaluations) {
  // refine_direction evaluates its starts in one RefineObjective::values batch (lune_moments stage
  // by stage); each must equal value() of that direction bit for bit, both ratio forms, batches
  // longer than the internal block of 8 included.
  const ShImage sh = random_lighting_set(200, 9);
  std::mt19937 rng(4);
  std::normal_distribution<double> g;
  for (int form = 0; form < 2; ++form)
    for (size_t i = 0; i < sh.texels(); ++i) {
      IrradiancePoly p[3];
      double iz[3];
      polys_and_iz(sh, i, p, iz);
      const RefineObjective f(p, iz, form ? RatioForm::Luminance : RatioForm::Rgb);
      double dirs[11][3];
      const double* ptr[11];
      for (int k = 0; k < 11; ++k) {
        double len = 0;
        for (double& x : dirs[k]) x = g(rng), len += x * x;
        for (double& x : dirs[k]) x /= std::sqrt(len);
        dirs[k][2] = std::fabs(dirs[k][2]);
        if (k == 7) dirs[k][2] = -dirs[k][2];  // one below the horizon: lune_moments' libm branch
        ptr[k] = dirs[k];
      }
      double batch[11];
      f.values(ptr, 11, batch);
      for (int k = 0; k < 11; ++k) {
        const double single = f.value(dirs[k]);
        ASSERT_EQ(std::memcmp(&single, &batch[k], sizeof single), 0) << "texel " << i << " dir " << k;
      }
    }
}

TEST(FitRefine, HandedOverMomentsGiveTheSameBytesAsRecomputedOnes) {
  // fit_texel hands the refinement's lune moments of the chosen d to fit_colours (and the polish
  // takes the best start's gradient from the batch's moments): the fit must equal fit_colours at
  // that d with the moments recomputed, bit for bit, both ratio forms; and
  // RefineObjective::gradient_at must equal value_grad's gradient.
  const ShImage sh = random_lighting_set(3000, 17);
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
    const FitOptions opt = options(form, DirectionFit::Refined);
    int moved = 0;
    for (size_t i = 0; i < sh.texels(); ++i) {
      IrradiancePoly p[3];
      double iz[3], d[3];
      polys_and_iz(sh, i, p, iz);
      if (!optimal_direction(p, opt, d)) continue;
      tilt_above_horizon(d, opt.dz_min);
      const double d0[3] = {d[0], d[1], d[2]};
      LuneMoments m;
      refine_direction(p, iz, opt, d, RefineSearch{}, nullptr, &m);
      moved += d[0] != d0[0] || d[1] != d0[1] || d[2] != d0[2];
      const AhdFit a = fit_colours(p, d, iz, opt, &m), b = fit_colours(p, d, iz, opt);
      ASSERT_EQ(std::memcmp(&a, &b, offsetof(AhdFit, flags) + 1), 0) << "texel " << i;
      const AhdFit t = fit_texel(p, opt);
      ASSERT_EQ(std::memcmp(t.ratio, a.ratio, sizeof a.ratio), 0) << "texel " << i;
      ASSERT_EQ(std::memcmp(t.d, a.d, sizeof a.d), 0) << "texel " << i;
      const RefineObjective f(p, iz, form);
      double g1[3], g2[3];
      f.value_grad(d, g1);
      f.gradient_at(d, m, g2);
      ASSERT_EQ(std::memcmp(g1, g2, sizeof g1), 0) << "texel " << i;
    }
    EXPECT_GT(moved, 2000);
  }
}

TEST(FitRefine, LockstepLanesGiveTheSameBytesAsOneTexelAtATime) {
  // fit_texels runs up to kRefineLanes texels' refinements in lockstep (refine_direction_lanes:
  // their lune moments in one batch per stage, lanes finishing at different steps); each texel
  // must get fit_texel's bytes alone (the lanes' directions, moments and colours kept apart). A
  // random mix of texels: random lighting, constant irradiance (no refinement), no direction (L1
  // cancelled), in groups of 1–4, both ratio forms, L1 and L2; also refine_direction_lanes against
  // refine_direction with the moments it hands on.
  const ShImage sh = random_lighting_set(2000, 23);
  std::mt19937 rng(5);
  std::vector<IrradiancePoly> polys(sh.texels() * 3);
  for (size_t i = 0; i < sh.texels(); ++i) {
    IrradiancePoly* p = &polys[i * 3];
    local_polys(sh, i, p);
    const int kind = int(rng() % 8);
    if (kind == 0)
      for (int c = 0; c < 3; ++c) p[c] = IrradiancePoly{}, p[c].e0 = 0.5 + c;  // constant
    if (kind == 1)
      for (int c = 0; c < 3; ++c) p[c].e[0] = p[c].e[1] = p[c].e[2] = 0;  // no direction, L2 left
  }
  auto constant = [](const IrradiancePoly* p) {
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) {
        if (p[c].e[i] != 0.0) return false;
        for (int j = 0; j < 3; ++j)
          if (p[c].q[i][j] != 0.0) return false;
      }
    return true;
  };
  for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance})
    for (DirectionFit dir : {DirectionFit::Refined, DirectionFit::Linear}) {
      const FitOptions opt = options(form, dir);
      int groups_with_several_refined = 0;
      for (size_t i0 = 0; i0 < sh.texels();) {
        const int n = std::min<int>(1 + int(rng() % kRefineLanes), int(sh.texels() - i0));
        AhdFit group[kRefineLanes];
        float lin[3 * kRefineLanes];
        fit_texels(&polys[i0 * 3], n, opt, group, lin);
        int refined = 0;
        for (int k = 0; k < n; ++k) {
          float lin1[3];
          const AhdFit one = fit_texel(&polys[(i0 + k) * 3], opt, lin1);
          ASSERT_EQ(std::memcmp(&one, &group[k], offsetof(AhdFit, flags) + 1), 0) << "texel " << i0 + k;
          ASSERT_EQ(std::memcmp(lin1, &lin[3 * k], sizeof lin1), 0) << "texel " << i0 + k;
          refined += !(one.flags & kFitNoDirection) && !constant(&polys[(i0 + k) * 3]);
        }
        groups_with_several_refined += refined >= 2;
        i0 += size_t(n);
      }
      EXPECT_GT(groups_with_several_refined, 300);  // the lockstep path was exercised
    }
  // The lanes API itself: four texels against refine_direction one by one, d and moments.
  const FitOptions opt = options(RatioForm::Rgb, DirectionFit::Refined);
  for (size_t i0 = 0; i0 + 4 <= 400; i0 += 4) {
    double iz[4][3], d[4][3], d1[4][3];
    const IrradiancePoly* lp[4];
    const double* liz[4];
    double* ld[4];
    LuneMoments m[4];
    for (int k = 0; k < 4; ++k) {
      lp[k] = &polys[(i0 + k) * 3], liz[k] = iz[k], ld[k] = d[k];
      for (int c = 0; c < 3; ++c) iz[k][c] = std::max(0.0, lp[k][c].e0 + lp[k][c].e[2] + lp[k][c].q[2][2]);
      optimal_direction(lp[k], opt, d[k]);
      tilt_above_horizon(d[k], opt.dz_min);
      std::memcpy(d1[k], d[k], sizeof d1[k]);
    }
    refine_direction_lanes(4, lp, liz, opt, ld, m);
    for (int k = 0; k < 4; ++k) {
      LuneMoments m1;
      refine_direction(lp[k], iz[k], opt, d1[k], RefineSearch{}, nullptr, &m1);
      ASSERT_EQ(std::memcmp(d1[k], d[k], sizeof d1[k]), 0) << "texel " << i0 + k;
      ASSERT_EQ(std::memcmp(&m1, &m[k], sizeof m1), 0) << "texel " << i0 + k;
    }
  }
}

namespace ahd {
namespace {

// A smooth lit scene with Monte-Carlo-like noise: the case the window is for.
ShImage noisy_scene() {
  ShImage sh = calibrated_smooth_scene();
  uint32_t state = 12345;
  for (float& v : sh.data) {
    state = state * 1664525u + 1013904223u;
    v *= 1.0f + 0.3f * (float(state >> 8) / float(1u << 24) - 0.5f);
  }
  return sh;
}

TEST(FitWindow, GuardBoundsEveryNeighbourAngleByTheWindowsLinearField) {
  // The windowed fit's pair guard (direction_guard.h with a revert): every adjacent covered pair
  // turns by at most max(T, the angle of the window's linear d, the angle of the texels' own linear
  // d), a reverted texel stores exactly
  // the window's linear d with its own I_z, and the bytes are the same on 1 and 3 threads.
  for (const ShImage& sh : {smooth_scene(), noisy_scene()})
    for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance}) {
      FitOptions win = options(form, DirectionFit::Refined);
      win.direction_window = 1;
      FitStats st;
      const AhdImage a = fit_image(sh, win, 1, &st), b = fit_image(sh, win, 3);
      const AhdImage l = fit_image(sh, options(form, DirectionFit::Linear), 2);
      const size_t w = size_t(sh.width), n = sh.texels();
      std::vector<float> wl(n * 3);
      for (size_t i = 0; i < n; ++i) {
        ASSERT_TRUE(same_fit_bits(a.texel(i), b.texel(i))) << "texel " << i;
        IrradiancePoly p[3];
        window_local_polys(sh, i, 1, p);
        linear_direction(p, win, &wl[i * 3]);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a.iz[i * 3 + c], l.iz[i * 3 + c]) << "I_z is the texel's own, exactly";
      }
      size_t pairs = 0;
      for (size_t i = 0; i < n; ++i)
        for (size_t j : {i + 1, i + w}) {
          if ((j == i + 1 && (i + 1) % w == 0) || j >= n || !sh.coverage[i] || !sh.coverage[j]) continue;
          ++pairs;
          ASSERT_LE(neighbour_angle_deg(&a.d[i * 3], &a.d[j * 3]),
                    std::max({win.pair_guard_deg, neighbour_angle_deg(&wl[i * 3], &wl[j * 3]),
                              neighbour_angle_deg(&l.d[i * 3], &l.d[j * 3])}))
              << "pair " << i << ", " << j;
        }
      EXPECT_GT(pairs, 3000u);
      EXPECT_GT(st.guard_reverted, 0u);  // the guard had something to do
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

}  // namespace
}  // namespace ahd

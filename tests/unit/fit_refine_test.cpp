// Issue 18: the refined direction and the least-squares luminance ratio: the gradient, the ratio
// against brute force, the closed-loop refit, hard cases, the intermediate's record of it, the
// fast paths' bytes, and the window's pair guard. The sweeps over many inputs (error ratios,
// 10⁶ random texels, never worse than the paper's choice): tests/accuracy/fit_refine_test.cpp.
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


// What the error-estimate tests share (tests/unit, tests/accuracy, tests/integration
// error_estimate_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include "image/image_io.h"
#include "files/profile_file.h"
#include "cli_runner.h"
#include "fit/hemisphere_error.h"
#include "pipeline/convert.h"
#include "pipeline/profile.h"
#include "sample/analytic_baker.h"

namespace ahd_fixture::error_estimate_fixture {

using namespace ::ahd;

inline ShImage estimate_scene(int size, int coeffs = 9) {
  BakerOptions bo;
  bo.width = bo.height = size;
  bo.coeffs = coeffs;
  return bake_analytic_scene(bo);
}

// A plain lightmap as the `plain` layout reads it: L0 only (E/π along the normal), no L1.
inline ShImage plain_of(const ShImage& sh) {
  ShImage p = make_sh_image(sh.width, sh.height, 4);
  p.coverage = sh.coverage;
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int c = 0; c < 3; ++c) p.texel(i)[c] = sh.texel(i)[c];
  return p;
}

// What a pc-bc conversion's files decode to at level 0, as lobes.
inline std::vector<AhdLobe> final_lobes(const ShImage& sh, PipelineResult* r) {
  PipelineOptions opt;
  opt.measure = Measure::Off;
  *r = run_conversion(sh, load_profile("pc-bc"), opt);
  return lobes_from_planes(decode_planes(r->planes, false, 0), opt.fit.dz_min);
}

inline std::vector<AhdLobe> fit_lobes(const ShImage& sh) {
  PipelineOptions opt;
  opt.measure = Measure::Off;
  opt.max_levels = 1;
  PipelineResult r;
  const auto levels = fit_levels(sh, opt, &r);
  std::vector<AhdLobe> lobes(sh.texels());
  for (size_t i = 0; i < lobes.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      lobes[i].ca[c] = fitted_ca(levels[0].ahd.texel(i), c);
      lobes[i].cd[c] = fitted_cd(levels[0].ahd.texel(i), c);
      lobes[i].d[c] = levels[0].ahd.texel(i).d[c];
    }
  return lobes;
}

// The stated tolerance of the estimate (docs/performance.md "The error estimate", hemisphere_error.h): mean within 3 %, p99 within
// 10 % of the full figure (relative to it), or within `floor` absolute for figures near zero.
// Why 10 % for the p99: the sample's p99 stands at a true quantile of 0.99 ± 0.0016 (one standard
// error at 4096 texels); on the heavy-tailed BC6H errors of a plain map that rank band is ±6 % in
// value (measured +6.4 %), on the sample scene under 2 %.
inline void expect_agrees(const ErrorStat& est, const ErrorStat& full, double floor, const char* what) {
  std::printf("  %-9s mean %.4g vs %.4g (%+.2f %%), p99 %.4g vs %.4g (%+.2f %%)\n", what, est.mean, full.mean,
              100 * (est.mean / full.mean - 1), est.p99, full.p99, 100 * (est.p99 / full.p99 - 1));
  EXPECT_NEAR(est.mean, full.mean, std::max(0.03 * full.mean, floor)) << what << " mean";
  EXPECT_NEAR(est.p99, full.p99, std::max(0.10 * full.p99, floor)) << what << " p99";
  EXPECT_LE(est.max, full.max) << what << " max (the sample's max bounds it from below)";
}

inline void expect_estimate_agrees(const ShImage& sh, const std::vector<AhdLobe>& lobes, double floor) {
  const ErrorReport full = measure_error(sh, lobes, 0);
  const ErrorReport est = estimate_error(sh, lobes, 0);
  ASSERT_GT(full.texels, size_t(kErrorSampleSize)) << "the image must be larger than the sample";
  EXPECT_EQ(est.texels, size_t(kErrorSampleSize));
  EXPECT_EQ(est.population, full.texels);
  expect_agrees(est.relative, full.relative, floor, "relative");
  expect_agrees(est.rmse, full.rmse, floor * 1e-3, "rmse");
  expect_agrees(est.log2, full.log2, floor, "log2");
}

}  // namespace ahd_fixture::error_estimate_fixture

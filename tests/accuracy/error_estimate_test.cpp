// The sampled error estimate against the full measurement, on the sample scene, a plain lightmap
// and a whole conversion. Unit tests: tests/unit/error_estimate_test.cpp.
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
#include "error_estimate_fixture.h"

using namespace ahd;
using namespace ahd_fixture::error_estimate_fixture;


TEST(ErrorEstimate, AgreesWithFullMeasurementOnTheSampleScene) {
  const ShImage sh = estimate_scene(256);
  expect_estimate_agrees(sh, fit_lobes(sh), 1e-4);
  PipelineResult r;
  const auto lobes = final_lobes(sh, &r);
  expect_estimate_agrees(sh, lobes, 1e-4);
  // Thread count does not change it.
  const ErrorReport a = estimate_error(sh, lobes, 1), b = estimate_error(sh, lobes, 3);
  EXPECT_EQ(a.relative.p99, b.relative.p99);
  EXPECT_EQ(a.log2.mean, b.log2.mean);
}

TEST(ErrorEstimate, AgreesWithFullMeasurementOnAPlainLightmap) {
  const ShImage p = plain_of(estimate_scene(256, 4));
  PipelineResult r;
  const auto lobes = final_lobes(p, &r);
  EXPECT_FALSE(r.directional);
  // The plain map's error is BC6H's alone (≈ 1e-2 relative); near-zero figures get an absolute floor.
  expect_estimate_agrees(p, lobes, 2e-4);
}

// What `ahdpack convert` prints by default (Measure::Estimate) against `--measure full`, through the
// whole conversion of the built-in sample: every level's quantised error, mean within 3 % and p99
// within 10 % (the tolerance stated in fit/hemisphere_error.h), and the fit's error likewise.
TEST(ErrorEstimate, ConversionEstimateAgreesWithFullMeasurement) {
  BakerOptions bo;
  bo.width = bo.height = 256;  // the built-in sample: 65 536 texels, far more than the 4096 sampled
  const ShImage sh = bake_analytic_scene(bo);
  PipelineOptions est, full;
  est.measure = Measure::Estimate;
  full.measure = Measure::Full;
  const Profile p = load_profile("pc-bc");
  const PipelineResult e = run_conversion(sh, p, est), f = run_conversion(sh, p, full);
  ASSERT_EQ(e.level_error.size(), f.level_error.size());
  EXPECT_LT(e.final_error.texels, f.final_error.texels);  // level 0 really was sampled
  EXPECT_EQ(e.final_error.population, f.final_error.texels);
  for (size_t l = 0; l < f.level_error.size(); ++l) {
    const ErrorReport &a = e.level_error[l], &b = f.level_error[l];
    EXPECT_NEAR(a.relative.mean, b.relative.mean, 0.03 * b.relative.mean) << "level " << l;
    EXPECT_NEAR(a.relative.p99, b.relative.p99, 0.10 * b.relative.p99) << "level " << l;
    EXPECT_NEAR(a.log2.mean, b.log2.mean, 0.03 * b.log2.mean) << "level " << l;
  }
  EXPECT_NEAR(e.fit_error.relative.mean, f.fit_error.relative.mean, 0.03 * f.fit_error.relative.mean);
  EXPECT_NEAR(e.fit_error.relative.p99, f.fit_error.relative.p99, 0.10 * f.fit_error.relative.p99);
  // The planes do not depend on what is measured.
  ASSERT_EQ(e.planes.size(), f.planes.size());
  for (size_t i = 0; i < f.planes.size(); ++i)
    for (size_t l = 0; l < f.planes[i].texture.levels.size(); ++l)
      EXPECT_EQ(e.planes[i].texture.levels[l].data, f.planes[i].texture.levels[l].data);
}

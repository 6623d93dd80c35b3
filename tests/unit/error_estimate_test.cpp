// The sampled error estimate (what a conversion prints by default): the fixed sample itself and the
// sampled direction decision. Against the full measurement: tests/accuracy/error_estimate_test.cpp.
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

TEST(ErrorEstimate, SampleIsFixedStratifiedAndCovered) {
  std::vector<uint8_t> cov(100000, 0);
  for (size_t i = 0; i < cov.size(); ++i) cov[i] = (i / 37) % 3 != 0;  // stripes of covered texels
  const auto s = error_sample(cov, 1000);
  ASSERT_EQ(s.size(), 1000u);
  EXPECT_EQ(s, error_sample(cov, 1000));  // deterministic
  EXPECT_TRUE(std::is_sorted(s.begin(), s.end()));
  EXPECT_EQ(std::adjacent_find(s.begin(), s.end()), s.end());  // no repeats
  for (size_t i : s) EXPECT_TRUE(cov[i]);
  // One pick per stratum: the k-th pick's covered rank lies in [k·N/K, (k+1)·N/K).
  std::vector<size_t> rank(cov.size());
  size_t n = 0;
  for (size_t i = 0; i < cov.size(); ++i) rank[i] = cov[i] ? n++ : 0;
  for (size_t k = 0; k < s.size(); ++k) {
    EXPECT_GE(rank[s[k]], k * n / 1000);
    EXPECT_LT(rank[s[k]], (k + 1) * n / 1000);
  }
  // Fewer covered texels than the sample: all of them.
  std::vector<uint8_t> few(50, 0);
  few[3] = few[17] = few[49] = 1;
  EXPECT_EQ(error_sample(few, 1000), (std::vector<size_t>{3, 17, 49}));
}

// The picks are pinned (FNV-1a of the indices, from the first implementation's straight scan) so
// that a faster scan cannot move the sample, and with it every estimate a report prints.
TEST(ErrorEstimate, SamplePicksArePinned) {
  const unsigned long long expected[3] = {0xb2df618e2e2627a5ull, 0x17ad381b58d6b23aull, 0xeb1072ee8184a5a7ull};
  for (int pat = 0; pat < 3; ++pat) {
    std::vector<uint8_t> cov(2048 * 1024 + 77, 0);
    std::mt19937 rng(pat);
    for (size_t i = 0; i < cov.size(); ++i)
      cov[i] = pat == 0 ? (i / 37) % 3 != 0 : pat == 1 ? (rng() % 7) < 3 : ((i % 2048) < 1500 && (i / 2048) % 100 < 60);
    const auto s = error_sample(cov, 4096);
    ASSERT_EQ(s.size(), 4096u);
    unsigned long long h = 1469598103934665603ull;
    for (size_t v : s) h = (h ^ v) * 1099511628211ull;
    EXPECT_EQ(h, expected[pat]) << "pattern " << pat;
  }
}

TEST(ErrorEstimate, SmallImagesAreMeasuredExactly) {
  const ShImage sh = estimate_scene(48);  // < 4096 covered texels: the estimate is the full measurement
  const auto lobes = fit_lobes(sh);
  const ErrorReport full = measure_error(sh, lobes, 0), est = estimate_error(sh, lobes, 1);
  EXPECT_EQ(est.texels, full.texels);
  EXPECT_EQ(est.relative.mean, full.relative.mean);
  EXPECT_EQ(est.relative.p99, full.relative.p99);
  EXPECT_EQ(est.log2.max, full.log2.max);
  EXPECT_EQ(est.normal_rel.p99, full.normal_rel.p99);
}

TEST(ErrorEstimate, FiguresAreThoseOfTheSortedTexels) {
  // Every figure of a report against texel_error's values sorted: the mean in raster order, the max,
  // and the p99 = the value at sorted index ceil(0.99·n) − 1 (a selection picks it, not a sort) —
  // on 64² (4 096 texels: 41 above it), 30² (one: the max) and 101² (103).
  for (int size : {64, 30, 101}) {
    const ShImage sh = estimate_scene(size);
    const auto lobes = fit_lobes(sh);
    const ErrorReport r = measure_error(sh, lobes, 2);
    const std::vector<double> dirs = hemisphere_directions(64);
    std::vector<double> rel, lg;
    double sum = 0;
    for (size_t i = 0; i < sh.texels(); ++i) {
      if (!sh.coverage[i]) continue;
      const TexelError e = texel_error(sh, i, lobes[i], dirs.data(), 64);
      rel.push_back(e.rel), lg.push_back(e.lg), sum += e.rel;
    }
    ASSERT_EQ(r.texels, rel.size());
    std::sort(rel.begin(), rel.end());
    std::sort(lg.begin(), lg.end());
    const size_t k = size_t(std::ceil(0.99 * double(rel.size()))) - 1;
    EXPECT_EQ(r.relative.mean, sum / double(rel.size())) << size;
    EXPECT_EQ(r.relative.max, rel.back()) << size;
    EXPECT_EQ(r.relative.p99, rel[k]) << size;
    EXPECT_EQ(r.log2.p99, lg[k]) << size;
    EXPECT_LT(r.relative.p99, r.relative.max) << size;  // a p99 that is not simply the max
  }
}

TEST(ErrorEstimate, DirectionDecisionShortcuts) {
  const ShImage sh = estimate_scene(64);
  const ShImage p = plain_of(sh);
  EXPECT_FALSE(sh_is_constant(sh));
  EXPECT_TRUE(sh_is_constant(p));
  ShImage one = p;  // a single nonzero L2 coefficient is enough to need the evaluation
  one.texel(77)[20] = 1e-30f;
  EXPECT_FALSE(sh_is_constant(p.coeffs == 4 ? sh : one));
  // On an image no larger than the sample, the sampled decision is the full one, both ways.
  const auto lobes = fit_lobes(sh);
  std::vector<AhdLobe> ambient(sh.texels());
  for (size_t i = 0; i < sh.texels(); ++i) ambient[i] = {{lobes[i].ca[0] + lobes[i].cd[0] * lobes[i].d[2],
                                                          lobes[i].ca[1] + lobes[i].cd[1] * lobes[i].d[2],
                                                          lobes[i].ca[2] + lobes[i].cd[2] * lobes[i].d[2]},
                                                         {0, 0, 0},
                                                         {0, 0, 1}};
  const double p99 = measure_error(sh, ambient, 0).relative.p99;
  const LobeAt at = [&](size_t i) { return ambient[i]; };
  EXPECT_TRUE(sampled_relative_p99_exceeds(sh, at, p99 * 0.999));
  EXPECT_FALSE(sampled_relative_p99_exceeds(sh, at, p99 * 1.001));
  EXPECT_EQ(sampled_relative_p99_exceeds(sh, at, 0.01), relative_p99_exceeds(sh, ambient, 0.01));
}

// The error figures' inner loop (fit/hemisphere_sums.h): its log2 against std::log2, and its AVX2
// path against the plain one, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/cpu.h"
#include "fit/hemisphere_sums.h"

using namespace ahd;

namespace {

uint64_t bits_of(double x) {
  uint64_t b;
  std::memcpy(&b, &x, 8);
  return b;
}

}  // namespace

TEST(HemisphereSums, Log2SeriesIsWithinFourUlpOfStdLog2) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> e(-60, 60);
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const double x = std::exp2(e(rng));
    const double want = std::log2(x), got = log2_series(x);
    const double ulp = std::nextafter(std::fabs(want), INFINITY) - std::fabs(want);
    worst = std::max(worst, std::fabs(got - want) / std::max(ulp, std::numeric_limits<double>::denorm_min()));
    ASSERT_LE(std::fabs(got - want), 4 * ulp + 1e-300) << x;
  }
  std::printf("worst error: %.2f ulp\n", worst);
  // Exact where the logarithm is: powers of two, and 1.
  for (int k = -1000; k <= 1000; ++k) EXPECT_EQ(log2_series(std::ldexp(1.0, k)), double(k));
  // Outside the normal doubles it is std::log2.
  for (double x : {0.0, 1e-310, double(INFINITY), -1.0})
    EXPECT_EQ(bits_of(log2_series(x)), bits_of(std::log2(x))) << x;
  EXPECT_TRUE(std::isnan(log2_series(std::nan(""))));
}

TEST(HemisphereSums, PathsGiveTheSameBits) {
  if (!cpu::has(cpu::kAvx2)) GTEST_SKIP() << "no AVX2 on this CPU: only the plain path runs";
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> dirs;
  // AVX-512 where the CPU has it (the wider path is compared with the plain one too).
  const bool avx512 = cpu::has(cpu::kAvx2 | cpu::kAvx512);
  for (int k = 0; k < 67; ++k) {  // not a multiple of four: the AVX2 path's tail too
    const double z = (k + 0.5) / 67, r = std::sqrt(1 - z * z), a = 2.399963 * k;
    dirs.insert(dirs.end(), {r * std::cos(a), r * std::sin(a), z});
  }
  int checked = 0, checked512 = 0;
  for (int t = 0; t < 3000; ++t) {
    IrradiancePoly p[3];
    for (IrradiancePoly& q : p) {
      q.e0 = 1 + u(rng);
      for (double& v : q.e) v = 0.7 * u(rng);
      for (auto& row : q.q)
        for (double& v : row) v = 0.3 * u(rng);
    }
    // A third of the texels L1 (q = ±0: the wide paths skip those terms), one in nine of them with a
    // channel of signed zeros (ref = −0 on some directions, +0 on the plain path's).
    if (t % 3 == 1)
      for (IrradiancePoly& q : p)
        for (auto& row : q.q)
          for (double& v : row) v = t % 2 ? 0.0 : -0.0;
    if (t % 9 == 4) p[0].e0 = -0.0, p[0].e[0] = p[0].e[1] = p[0].e[2] = -0.0;
    AhdLobe l{};
    for (int c = 0; c < 3; ++c) l.ca[c] = 0.5 + u(rng), l.cd[c] = (t % 7 == 0 ? -1 : 1) * (0.5 + u(rng)), l.d[c] = u(rng);
    if (t % 11 == 0) l.ca[0] = 1e300 * (1 + u(rng));  // ratios far out: the log of huge values
    if (t % 13 == 0) l.ca[1] = std::numeric_limits<double>::infinity();  // std::log2's cases: the plain path
    for (int n : {1, 4, 5, 8, 13, 64, 67}) {  // 13, 67: a group of four and a tail after the eights
      for (bool with_log : {false, true}) {
        const HemisphereSums a = hemisphere_sums_plain(p, l, dirs.data(), n, with_log);
        const HemisphereSums b = hemisphere_sums_avx2(p, l, dirs.data(), n, with_log);
        ASSERT_EQ(bits_of(a.se), bits_of(b.se)) << t << " " << n;
        ASSERT_EQ(bits_of(a.sl), bits_of(b.sl)) << t << " " << n;
        ASSERT_EQ(bits_of(a.lum), bits_of(b.lum)) << t << " " << n;
        ++checked;
        if (!avx512) continue;
        const HemisphereSums c = hemisphere_sums_avx512(p, l, dirs.data(), n, with_log);
        ASSERT_EQ(bits_of(a.se), bits_of(c.se)) << "AVX-512 " << t << " " << n;
        ASSERT_EQ(bits_of(a.sl), bits_of(c.sl)) << "AVX-512 " << t << " " << n;
        ASSERT_EQ(bits_of(a.lum), bits_of(c.lum)) << "AVX-512 " << t << " " << n;
        ++checked512;
      }
    }
  }
  EXPECT_EQ(checked, 3000 * 14);
  EXPECT_EQ(checked512, avx512 ? 3000 * 14 : 0);
}

// `ahdpack preview`. PreviewChromium.*: the page in a real browser: Debian's chromium, headless, opens the page from file://.
// The page must load every image and run its script without an error, the screenshot must not be
// blank, and the error heat map must be darker where the analytic scene is smooth than at its
// shadow edges. Skipped only when chromium is not installed (scripts/setup.sh installs it).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli_runner.h"
#include "image/image_io.h"
#include "image/sh_exr.h"
#include "sh/sh_image.h"
#include "file_bytes.h"
#include "test_data.h"
#include "preview_chromium_fixture.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

using namespace ahd_fixture::preview_chromium_fixture;


// Where the scene is smooth the BC6H/BC5 planes are nearly exact; at the hard and soft shadow
// edges (and the sphere's contact) a 4×4 block holds light and shadow and the error along the
// normal rises. Edges are found from the source itself: the relative jump of E(z) to a neighbour.
TEST(Preview, HeatMapIsDarkerWhereSmoothThanAtShadowEdges) {
  Page p("preview_heat");
  const ahd::ShImage sh = ahd::read_canonical_sh(p.src.string());
  const ahd::ImageF heat = ahd::read_image((p.out / "error_normal.png").string());
  ASSERT_EQ(heat.width, sh.width);
  const int w = sh.width, h = sh.height;
  std::vector<double> ez(sh.texels());
  for (size_t i = 0; i < ez.size(); ++i) {
    ahd::IrradiancePoly poly[3];
    ahd::local_polys(sh, i, poly);
    const double z[3] = {0, 0, 1};
    ez[i] = 0.2126 * ahd::eval_irradiance(poly[0], z) + 0.7152 * ahd::eval_irradiance(poly[1], z) +
            0.0722 * ahd::eval_irradiance(poly[2], z);
  }
  std::vector<std::pair<double, size_t>> jumps;  // relative jump, texel: interior covered texels only
  for (int y = 2; y < h - 2; ++y)
    for (int x = 2; x < w - 2; ++x) {
      bool inside = true;
      double jump = 0;
      const size_t i = size_t(y) * w + x;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const size_t j = size_t(y + dy) * w + (x + dx);
          inside &= sh.coverage[j] != 0;
          if (std::abs(dx) + std::abs(dy) == 1) jump = std::max(jump, std::fabs(ez[j] - ez[i]) / std::max(ez[i], 1e-6));
        }
      if (inside) jumps.push_back({jump, i});
    }
  ASSERT_GT(jumps.size(), 1000u);
  std::sort(jumps.begin(), jumps.end());
  auto mean_heat = [&](size_t from, size_t to) {
    double s = 0;
    for (size_t k = from; k < to; ++k) s += luminance(heat, jumps[k].second);
    return s / double(to - from);
  };
  const size_t n = jumps.size();
  const double smooth = mean_heat(0, n / 2), edges = mean_heat(n - n / 20, n);  // lower half vs top 5 %
  std::printf("heat-map luminance: smooth %.3f, shadow edges %.3f\n", smooth, edges);
  EXPECT_LT(smooth * 1.3, edges);  // measured 0.241 vs 0.389 (pc-bc, 128²)
}

TEST(Preview, BadInputWritesNoFolder) {
  const fs::path d = ahd_test::temp_dir("preview_bad");
  const auto r = run_cli({"preview", (d / "missing.json").string(), "-o", (d / "page").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(d / "page"));
  for (const auto& e : fs::directory_iterator(d)) ADD_FAILURE() << "left behind: " << e.path();
  // A folder that is not an earlier preview is never replaced.
  fs::create_directories(d / "mine");
  std::ofstream(d / "mine" / "keep.txt") << "x";
  ASSERT_EQ(run_cli({"sample", "-o", (d / "s.exr").string(), "--size", "16"}).exit_code, 0);
  ASSERT_EQ(run_cli({"convert", (d / "s.exr").string(), "-o", (d / "c" / "s.ktx2").string()}).exit_code, 0);
  const auto r2 = run_cli({"preview", (d / "c" / "s.json").string(), "-o", (d / "mine").string()});
  EXPECT_EQ(r2.exit_code, 1) << r2.output;
  EXPECT_TRUE(fs::exists(d / "mine" / "keep.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(d / "mine"), fs::directory_iterator()), 1);
}

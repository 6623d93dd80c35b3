// The real Godot 4.2 bake read through the godot4-packed layout against its source and Godot's
// runtime decode. Layout unit tests: tests/unit/baker_layout_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "cli_runner.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "layout_test_scene.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;


TEST(Layout, GodotPackedMatchesSourceAndGodotsRuntime) {
  const WorldBake b("layout_godot");
  const fs::path& d = b.dir;
  const WorldScene& w = b.w;
  write_godot_packed(w, b.file(".exr"));
  const ShImage sh = b.read("godot4-packed");
  const ImageF stored = read_image((d / "lm.exr").string());  // as the runtime samples it
  std::mt19937 rng(1);
  double worst = 0, worst_rt = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!w.tangent.coverage[i]) continue;
    for (const auto& n : directions(w, i, 8, rng))
      for (int c = 0; c < 3; ++c) {
        const double src = source_e_over_pi(w, i, c, n.data()), got = readback_e_over_pi(sh, i, c, n.data());
        double l0s;
        double l1s[3];
        world_linear(w, i, c, &l0s, l1s);
        worst = std::max(worst, std::fabs(got - src) / (std::fabs(l0s) + 1e-6));
        // Godot's runtime (forward_clustered): sh = L0 + L0*((t-0.5)*2)*n.y*4 + … (layers y, z, x).
        const int x = int(i % N), y = int(i / N);
        const double L0 = stored.at(x, y)[c];
        const double t[3] = {stored.at(x, y + N)[c], stored.at(x, y + 2 * N)[c], stored.at(x, y + 3 * N)[c]};
        const double runtime = L0 + L0 * (t[0] - 0.5) * 2 * n[1] * 4 + L0 * (t[1] - 0.5) * 2 * n[2] * 4 +
                               L0 * (t[2] - 0.5) * 2 * n[0] * 4;
        worst_rt = std::max(worst_rt, std::fabs(got - runtime) / (std::fabs(L0) + 1e-6));
      }
  }
  std::printf("godot4-packed: read-back vs source %.2e, vs Godot's runtime formula %.2e (relative to L0)\n", worst, worst_rt);
  EXPECT_LT(worst, 4e-3);     // half-float storage of L0 and t (2^-11 relative, ×8 for L1)
  EXPECT_LT(worst_rt, 1e-5);  // the same numbers through two formulas

  // `ahdpack decode` of the conversion along the surface normal equals the runtime along it
  // (×π: ahdpack's irradiance has no 1/π), within the fit's exactness and half precision.
  const auto r = ahd_test::run_cli({"convert", (d / "lm").string(), "--layout", "godot4-packed", "--normals",
                                    b.normals, "-o", (d / "out" / "a.ktx2").string(), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(ahd_test::run_cli({"decode", (d / "out" / "a.json").string(), "-o", (d / "e.exr").string()}).exit_code, 0);
  const ImageF e = read_image((d / "e.exr").string());
  double worst_decode = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!w.tangent.coverage[i]) continue;
    const int x = int(i % N), y = int(i / N);
    const double* n = &w.frame[i][6];
    for (int c = 0; c < 3; ++c) {
      const double L0 = stored.at(x, y)[c];
      const double t[3] = {stored.at(x, y + N)[c], stored.at(x, y + 2 * N)[c], stored.at(x, y + 3 * N)[c]};
      const double runtime = L0 + 8 * L0 * ((t[0] - 0.5) * n[1] + (t[1] - 0.5) * n[2] + (t[2] - 0.5) * n[0]);
      worst_decode = std::max(worst_decode, std::fabs(e.at(x, y)[c] / kPi - runtime) / (std::fabs(runtime) + 1e-6));
    }
  }
  std::printf("godot4-packed: ahdpack decode along the normal vs Godot's runtime %.2e\n", worst_decode);
  EXPECT_LT(worst_decode, 2e-3);
}

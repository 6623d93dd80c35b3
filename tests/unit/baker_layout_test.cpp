// Baker layouts: the analytic scene written in each preset's exact layout and encoding, read back
// to the canonical SH within that storage's precision; the bakers' own runtime formulas agree with
// our read-back and with `ahdpack decode` along the normal; every bad input gives one clear error.
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



TEST(Layout, GodotUnpackedMatchesSourceAndGodotsRuntime) {
  // Godot 4.0–4.3: one half EXR, layers L0, L1y, L1z, L1x stacked, signed raw radiance-SH
  // coefficients in world space; runtime E/π = 0.282095·L0 + 0.32573·(L1·n) (bakers.md).
  const WorldBake b("layout_godot_unpacked");
  const WorldScene& w = b.w;
  ImageF img(N, 4 * N, 3);
  for (size_t i = 0; i < w.tangent.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      double l0, l1[3];
      world_linear(w, i, c, &l0, l1);
      const int x = int(i % N), y = int(i / N);
      img.at(x, y)[c] = float(l0 / kY00);
      const double yzx[3] = {l1[1], l1[2], l1[0]};
      for (int k = 0; k < 3; ++k) img.at(x, y + (k + 1) * N)[c] = float(yzx[k] * 1.5 / kY1);
    }
  write_image(b.file(".exr"), img, /*half=*/true, {"R", "G", "B"});
  const ShImage sh = b.read("godot4-unpacked");
  const ImageF s = read_image(b.file(".exr"));
  std::mt19937 rng(3);
  double worst = 0, worst_rt = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!w.tangent.coverage[i]) continue;
    const int x = int(i % N), y = int(i / N);
    for (const auto& n : directions(w, i, 8, rng))
      for (int c = 0; c < 3; ++c) {
        double l0, l1[3];
        world_linear(w, i, c, &l0, l1);
        const double got = readback_e_over_pi(sh, i, c, n.data());
        worst = std::max(worst, std::fabs(got - source_e_over_pi(w, i, c, n.data())) / (l0 + 1e-6));
        const double runtime = s.at(x, y)[c] * 0.282095 +
                               (s.at(x, y + N)[c] * n[1] + s.at(x, y + 2 * N)[c] * n[2] + s.at(x, y + 3 * N)[c] * n[0]) * 0.32573;
        worst_rt = std::max(worst_rt, std::fabs(got - runtime) / (l0 + 1e-6));
      }
  }
  std::printf("godot4-unpacked: read-back vs source %.2e, vs Godot's runtime formula %.2e (relative to L0)\n", worst, worst_rt);
  EXPECT_LT(worst, 4 * 0.0005);  // half storage: 2^-11 relative on L0 and on each L1 term
  EXPECT_LT(worst_rt, 1e-4);      // Godot rounds (2/3)·Y1 = 0.325735 to 0.32573
}

TEST(Layout, BakerySh8BitAndRgbeWithinStoragePrecision) {
  const WorldBake b("layout_bakery");
  const fs::path& d = b.dir;
  const WorldScene& w = b.w;
  write_bakery_sh(w, b.base());
  const ShImage sh = b.read("bakery-sh");
  std::mt19937 rng(2);
  double worst = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!w.tangent.coverage[i]) continue;
    double a, b[3];
    world_linear(w, i, 1, &a, b);
    for (const auto& n : directions(w, i, 8, rng))
      worst = std::max(worst, std::fabs(readback_e_over_pi(sh, i, 1, n.data()) - source_e_over_pi(w, i, 1, n.data())) / a);
  }
  // Bakery's own runtime (BakerySH): L1 = (t*2-1)*L0*2 per axis, sh = L0 + n.x*L1x + n.y*L1y + n.z*L1z,
  // on the values as stored (RGBE-decoded L0, 8-bit t): our read-back must say the same.
  const ImageF sl0 = read_image((d / "lm_L0.hdr").string()), sx = read_image((d / "lm_L1x.tga").string()),
               sy = read_image((d / "lm_L1y.tga").string()), sz = read_image((d / "lm_L1z.tga").string());
  double worst_rt = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!w.tangent.coverage[i]) continue;
    for (const auto& n : directions(w, i, 4, rng))
      for (int c = 0; c < 3; ++c) {
        const double L0 = sl0.data[i * sl0.channels + c];
        const double L1x = (sx.data[i * sx.channels + c] * 2 - 1) * L0 * 2, L1y = (sy.data[i * sy.channels + c] * 2 - 1) * L0 * 2,
                     L1z = (sz.data[i * sz.channels + c] * 2 - 1) * L0 * 2;
        const double runtime = L0 + n[0] * L1x + n[1] * L1y + n[2] * L1z;
        worst_rt = std::max(worst_rt, std::fabs(readback_e_over_pi(sh, i, c, n.data()) - runtime) / (L0 + 1e-6));
      }
  }
  std::printf("bakery-sh: read-back vs source %.2e of L0, vs Bakery's runtime formula %.2e\n", worst, worst_rt);
  EXPECT_LT(worst_rt, 1e-5);
  // RGBE keeps ~1/128 relative; 8-bit t steps are 1/255 of ±2·L0 per axis: ≤ 1/128 + 3·4/510.
  EXPECT_LT(worst, 0.035);
}

TEST(Layout, PerCoefficientAndPlainAreExact) {
  const fs::path d = ahd_test::temp_dir("layout_percoef");
  BakerOptions bo;
  bo.width = bo.height = N;
  const ShImage src = bake_analytic_scene(bo);
  for (int k = 0; k < 9; ++k) {
    ImageF img(N, N, 3);
    for (size_t i = 0; i < src.texels(); ++i)
      for (int c = 0; c < 3; ++c) img.data[i * 3 + c] = src.texel(i)[k * 3 + c];
    write_image((d / ("lm_sh" + std::to_string(k) + ".exr")).string(), img);
  }
  const ShImage sh = read_layout(load_layout("per-coefficient"), (d / "lm").string(), "");
  EXPECT_EQ(sh.data, src.data);
  EXPECT_EQ(sh.coverage, src.coverage);  // the derived rule: all-zero SH = empty
  // Plain: E/π along the normal → pure ambient with I_z = π·value.
  ImageF plain(4, 4, 3);
  for (size_t i = 0; i < plain.data.size(); ++i) plain.data[i] = 0.25f + 0.01f * float(i);
  write_image((d / "flat.exr").string(), plain);
  const ShImage p = read_layout(load_layout("plain"), (d / "flat").string(), "");
  IrradiancePoly poly[3];
  local_polys(p, 5, poly);
  const double z[3] = {0, 0, 1}, side[3] = {1, 0, 0};
  EXPECT_NEAR(eval_irradiance(poly[1], z), kPi * plain.data[5 * 3 + 1], 1e-5);
  EXPECT_NEAR(eval_irradiance(poly[1], side), eval_irradiance(poly[1], z), 1e-6);
  fs::remove_all(d);
}

TEST(Layout, BadInputsGiveOneClearError) {
  const WorldBake b("layout_bad");
  const fs::path& d = b.dir;
  write_godot_packed(b.w, b.file(".exr"));
  const LayoutPreset godot = load_layout("godot4-packed"), bakery = load_layout("bakery-sh");
  expect_error([&] { read_layout(bakery, (d / "lm").string(), (d / "n.exr").string()); }, "lm_L0.hdr: file not found");
  expect_error([&] { read_layout(godot, (d / "lm").string(), ""); }, "--normals");
  ImageF zero(N, N, 3);
  write_image((d / "zero.exr").string(), zero);
  expect_error([&] { read_layout(godot, (d / "lm").string(), (d / "zero.exr").string()); }, "zero-length");
  ImageF odd(N, 4 * N + 1, 3);
  write_image((d / "odd.exr").string(), odd);
  expect_error([&] { read_layout(godot, (d / "odd").string(), (d / "n.exr").string()); }, "does not divide");
  ImageF small(N / 2, N / 2, 3);
  write_image((d / "small.exr").string(), small);
  expect_error([&] { read_layout(godot, (d / "lm").string(), (d / "small.exr").string()); }, "normal map is 8x8");
  ImageF ldr(N, 4 * N, 3);
  write_image((d / "ldr.png").string(), ldr);
  LayoutPreset png = godot;
  png.files[0].pattern = "{base}.png";
  expect_error([&] { read_layout(png, (d / "ldr").string(), (d / "n.exr").string()); }, "8-bit data");
  LayoutPreset alpha = godot;
  alpha.coefficients[0].source[0].channel = "A";
  expect_error([&] { read_layout(alpha, (d / "lm").string(), (d / "n.exr").string()); }, "no channel A");
  // Bakery: L1 files of another size.
  write_image((d / "b_L0.hdr").string(), ImageF(N, N, 3));
  for (const char* a : {"x", "y"}) write_image((d / (std::string("b_L1") + a + ".tga")).string(), ImageF(N, N, 3));
  write_image((d / "b_L1z.tga").string(), ImageF(N, N / 2, 3));
  expect_error([&] { read_layout(bakery, (d / "b").string(), (d / "n.exr").string()); }, "differs from the set");
  expect_error([&] { load_layout("no-such-baker"); }, "unknown layout 'no-such-baker'");
}

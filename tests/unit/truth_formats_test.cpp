// The bakers' directional formats of `report truth` (src/lab/truth_baker_formats.h) against
// the SH they come from. The path-traced accuracy figures: tests/accuracy/truth_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "api/options.h"
#include "fit/ahd_decode.h"
#include "lab/fit_quality.h"
#include "lab/truth_baker_formats.h"
#include "lab/truth_reference.h"
#include "lab/truth_file.h"
#include "pipeline/convert.h"
#include "pipeline/plane_decode.h"
#include "sh/sh_image.h"
#include "test_data.h"

namespace ahd {
namespace {

// The largest relative difference between a format's irradiance and the SH's own (clamped at 0),
// over every texel and three normals.
double worst_relative_to_sh(const ShImage& sh, const BakerFormatEval& f) {
  const double normals[3][3] = {{0, 0, 1}, {0.6, 0, 0.8}, {-0.48, 0.6, 0.64}};
  double rel = 0;
  for (size_t i = 0; i < sh.texels(); ++i)
    for (const auto& n : normals) {
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      double got[3];
      f.eval(i, n, got);
      for (int ch = 0; ch < 3; ++ch) {
        const double want = std::max(0.0, eval_irradiance(p[ch], n));
        rel = std::max(rel, std::abs(got[ch] - want) / std::max(want, 1e-3));
      }
    }
  return rel;
}

// The bakers' formats of `report truth` (lab/truth_baker_formats.h) decode what they claim to: for
// L1 SH whose light has one colour (every channel the same SH up to a factor), float MonoSH and
// float Godot L1 are both exactly the L1 SH's irradiance (clamped at 0); through BC6H and 8 bits
// they stay within a few per cent; and a coloured light separates MonoSH (one shared L1) from Godot.
TEST(TruthFormats, FloatFormatsAreTheL1ShAndQuantisedOnesStayClose) {
  const int w = 16, h = 16;
  ShImage sh = make_sh_image(w, h, 4);
  const double tint[3] = {1.0, 0.6, 0.3};
  for (size_t i = 0; i < sh.texels(); ++i) {
    const double u = double(i % w) / w, v = double(i / w) / h;
    const double c[4] = {1.0 + u, 0.3 * std::sin(6 * v), 0.4 * v, -0.25 * u};
    for (int k = 0; k < 4; ++k)
      for (int ch = 0; ch < 3; ++ch) sh.texel(i)[k * 3 + ch] = float(c[k] * tint[ch]);
  }
  auto worst = [&](const BakerFormatEval& f) { return worst_relative_to_sh(sh, f); };
  EXPECT_LT(worst(mono_sh_format(sh, false)), 1e-5);
  EXPECT_LT(worst(godot_l1_format(sh, false)), 1e-5);
  EXPECT_LT(worst(mono_sh_format(sh, true)), 0.05);
  EXPECT_LT(worst(godot_l1_format(sh, true)), 0.05);
  EXPECT_EQ(mono_sh_format(sh, true).bytes_per_texel, 5.0);
  EXPECT_EQ(godot_l1_format(sh, true).bytes_per_texel, 4.0);

  // Red light from +x, blue from −x: one shared L1 vector cannot hold both; per-channel L1 can.
  for (size_t i = 0; i < sh.texels(); ++i) {
    float* t = sh.texel(i);
    for (int k = 0; k < 12; ++k) t[k] = 0;
    for (int ch = 0; ch < 3; ++ch) t[ch] = 1.0f;
    t[3 * 3 + 0] = 0.5f;   // L1 x coefficient (c11), red
    t[3 * 3 + 2] = -0.5f;  // blue
  }
  EXPECT_LT(worst(godot_l1_format(sh, false)), 1e-5);
  EXPECT_GT(worst(mono_sh_format(sh, false)), 0.2);
}

// The engine anchors added for issue 43 (Godot's LDR directional texture, at full and half
// resolution; Unity's/Enlighten's dominant direction; the plain lightmap): float, the formats that
// are L1 SH for one-colour light equal it; quantised, their errors stay bounded; bytes as shipped.
TEST(TruthFormats, EngineAnchorsDecodeTheL1ShTheyStore) {
  const int w = 16, h = 16;
  const double tint[3] = {1.0, 0.6, 0.3};
  auto make = [&](bool constant_direction) {
    ShImage sh = make_sh_image(w, h, 4);
    for (size_t i = 0; i < sh.texels(); ++i) {
      const double u = double(i % w) / w, v = double(i / w) / h;
      double c[4] = {1.0 + u, 0.3 * std::sin(6 * v), 0.4 * v, -0.25 * u};
      if (constant_direction) c[1] = 0.3 * (1.0 + u), c[2] = 0.2 * (1.0 + u), c[3] = -0.1 * (1.0 + u);
      for (int k = 0; k < 4; ++k)
        for (int ch = 0; ch < 3; ++ch) sh.texel(i)[k * 3 + ch] = float(c[k] * tint[ch]);
    }
    return sh;
  };
  auto worst = [](const ShImage& sh, const BakerFormatEval& f) { return worst_relative_to_sh(sh, f); };
  const ShImage sh = make(false), flat = make(true);
  EXPECT_LT(worst(sh, godot_ldr_format(sh, false, 1)), 1e-5);
  EXPECT_LT(worst(sh, unity_directional_format(sh, false)), 1e-5);
  // Half resolution loses nothing where the direction does not change, and something where it does.
  EXPECT_LT(worst(flat, godot_ldr_format(flat, false, 2)), 1e-5);
  const double half = worst(sh, godot_ldr_format(sh, false, 2));
  EXPECT_GT(half, 1e-4);
  EXPECT_LT(half, 0.08);  // measured 0.050
  // Quantised (BC6H, 8 bits then BC1 / RGBA8).
  // BC1 holds t = Y(L1)/(8·Y(L0)) + 0.5 on 5- and 6-bit endpoints; the decode multiplies t − 0.5 by 8:
  // one 5-bit step is 0.26·L0 at a normal along that axis. Measured 0.145 and 0.181.
  EXPECT_LT(worst(sh, godot_ldr_format(sh, true, 1)), 0.2);
  EXPECT_LT(worst(sh, godot_ldr_format(sh, true, 2)), 0.25);
  EXPECT_LT(worst(sh, unity_directional_format(sh, true)), 0.05);
  // The plain lightmap is right along the normal only.
  const BakerFormatEval plain = plain_bc6h_format(sh);
  double got[3];
  IrradiancePoly p[3];
  local_polys(sh, 5, p);
  const double z[3] = {0, 0, 1};
  plain.eval(5, z, got);
  EXPECT_NEAR(got[0], eval_irradiance(p[0], z), 0.02 * eval_irradiance(p[0], z));
  EXPECT_GT(worst(sh, plain), 0.1);
  EXPECT_EQ(godot_ldr_format(sh, true, 1).bytes_per_texel, 1.5);
  EXPECT_EQ(godot_ldr_format(sh, true, 2).bytes_per_texel, 1.125);
  EXPECT_EQ(unity_directional_format(sh, true).bytes_per_texel, 2.0);
  EXPECT_EQ(plain.bytes_per_texel, 1.0);
  EXPECT_EQ(baker_formats(sh, true).size(), 6u);
}

}  // namespace
}  // namespace ahd

// The remaining baker presets (issue 8): three RGBA files (seed 001), Bakery MonoSH, Unity
// directional, multi-layer and multi-part EXR (L1 and L2). Each writes the analytic scene in the
// preset's exact layout and encoding, reads it back within the storage's precision, and checks the
// baker's own runtime formula on the stored files against our read-back; bad inputs give one error.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "layout_test_scene.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

// Worst err(i, c, n) over the covered texels × `count` random hemisphere directions × colours.
template <class Err>
double worst_over(const WorldScene& w, int count, unsigned seed, Err err) {
  std::mt19937 rng(seed);
  double worst = 0;
  for (size_t i = 0; i < w.tangent.texels(); ++i)
    if (w.tangent.coverage[i])
      for (const auto& n : directions(w, i, count, rng))
        for (int c = 0; c < 3; ++c) worst = std::max(worst, err(i, c, n.data()));
  return worst;
}

float stored(const ImageF& img, size_t i, int ch) { return img.data[i * size_t(img.channels) + size_t(ch)]; }

double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

double readback_luma(const ShImage& sh, size_t i, const double n[3]) {
  return readback_e_over_pi(sh, i, 0, n) + readback_e_over_pi(sh, i, 1, n) + readback_e_over_pi(sh, i, 2, n);
}

double source_luma(const WorldScene& w, size_t i, const double n[3]) {
  double l0, l1[3];
  world_linear_luma(w, i, &l0, l1);
  return l0 + dot3(l1, n);
}

// The L1 vector of a linear function f of the direction: (f(+e_a) − f(−e_a))/2 per axis.
template <class F>
std::array<double, 3> l1_of(F f) {
  std::array<double, 3> l1{};
  for (int a = 0; a < 3; ++a) {
    double e[3] = {0, 0, 0};
    e[a] = 1;
    const double plus = f(e);
    e[a] = -1;
    l1[size_t(a)] = (plus - f(e)) / 2;
  }
  return l1;
}

double angle_between(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  const double c = dot3(a.data(), b.data()) / std::sqrt(dot3(a.data(), a.data()) * dot3(b.data(), b.data()));
  return std::acos(std::clamp(c, -1.0, 1.0));
}

}  // namespace

TEST(Presets, ThreeRgbaHalfWithinStoragePrecisionAndSeedRuntime) {
  const WorldBake b("presets_rgba");
  const WorldScene& w = b.w;
  write_three_rgba(w, b.base());
  const ShImage sh = b.read("three-rgba");
  const double src_err = worst_over(w, 8, 3, [&](size_t i, int c, const double* n) {
    double l0, l1[3];
    world_linear(w, i, c, &l0, l1);
    return std::fabs(readback_e_over_pi(sh, i, c, n) - source_e_over_pi(w, i, c, n)) / (l0 + 1e-6);
  });
  // The seed's runtime: E/π = Σ Â_l c_lm Y_lm(n) / π = 0.282095·c0 + 0.325735·(c1 n.y + c2 n.z + c3 n.x),
  // on the half values as stored.
  const ImageF f[3] = {read_image(b.file("_r.exr")), read_image(b.file("_g.exr")), read_image(b.file("_b.exr"))};
  const double rt_err = worst_over(w, 8, 4, [&](size_t i, int c, const double* n) {
    const double c0 = stored(f[c], i, 0), l1[3] = {stored(f[c], i, 3), stored(f[c], i, 1), stored(f[c], i, 2)};
    const double runtime = kY00 * c0 + kY1 * 2 / 3 * dot3(l1, n);
    return std::fabs(readback_e_over_pi(sh, i, c, n) - runtime) / (kY00 * c0 + 1e-6);
  });
  std::printf("three-rgba: read-back vs source %.2e of L0, vs the seed's SH evaluation %.2e\n", src_err, rt_err);
  // Each half number is within 2^-11 relative; E/π = L0 + L1·n with |L1| ≤ 2·L0 for non-negative light.
  EXPECT_LT(src_err, 3 * std::ldexp(1.0, -11));
  EXPECT_LT(rt_err, 1e-5);  // the same numbers through two formulas (float rounding only)
}

TEST(Presets, BakeryMonoShKeepsLuminanceAndMatchesBakerysRuntime) {
  const WorldBake b("presets_monosh");
  const WorldScene& w = b.w;
  write_bakery_monosh(w, b.base());
  const ShImage sh = b.read("bakery-monosh");
  // MonoSH shares one L1 direction between colours, so only the luminance (what the encoder
  // projected) is kept, within RGBE and 8-bit precision.
  const double luma_err = worst_over(w, 8, 5, [&](size_t i, int, const double* n) {
    double l0, l1[3];
    world_linear_luma(w, i, &l0, l1);
    return std::fabs(readback_luma(sh, i, n) - source_luma(w, i, n)) / l0;
  });
  // Bakery's runtime (BakeryMonoSH, linear branch; z3y/ShaderGraph:ShaderLibrary/Bakery.hlsl):
  //   nL1 = dominantDir*2 - 1; L1x = nL1.x*L0*2; …; sh = L0 + n.x*L1x + n.y*L1y + n.z*L1z
  const ImageF sl0 = read_image(b.file("_L0.hdr")), sl1 = read_image(b.file("_L1.tga"));
  const double rt_err = worst_over(w, 8, 6, [&](size_t i, int c, const double* n) {
    const double nL1[3] = {stored(sl1, i, 0) * 2.0 - 1, stored(sl1, i, 1) * 2.0 - 1, stored(sl1, i, 2) * 2.0 - 1};
    const double L0 = stored(sl0, i, c);
    const double runtime = L0 + n[0] * nL1[0] * L0 * 2 + n[1] * nL1[1] * L0 * 2 + n[2] * nL1[2] * L0 * 2;
    return std::fabs(readback_e_over_pi(sh, i, c, n) - runtime) / (L0 + 1e-6);
  });
  std::printf("bakery-monosh: luminance read-back vs source %.2e, vs Bakery's MonoSH runtime %.2e\n", luma_err, rt_err);
  // RGBE (shared exponent, 8-bit mantissas) puts each colour of L0 within max/128 ≤ Λ/128, so
  // Λ = ΣL0 within 3/128; an 8-bit t is within 0.5/255, i.e. 4·0.5/255·Λ per axis (≤ √3·2/255·Λ
  // along n); |L1| ≤ 2Λ carries Λ's error twice: 3/128 + √3·2/255·(1 + 3/128) + 2·3/128.
  EXPECT_LT(luma_err, 3.0 / 128 + std::sqrt(3.0) * 2 / 255 * (1 + 3.0 / 128) + 6.0 / 128);
  EXPECT_LT(rt_err, 1e-5);
}

TEST(Presets, UnityDirectionalMatchesUnitysDecode) {
  const WorldBake b("presets_unity");
  const WorldScene& w = b.w;
  write_unity_directional(w, b.base());
  const ShImage sh = b.read("unity-directional");
  // UnityCG.cginc DecodeDirectionalLightmap on the stored files:
  //   halfLambert = dot(normalWorld, dirTex.xyz - 0.5) + 0.5; return color * halfLambert / max(1e-4h, dirTex.w);
  const ImageF light = read_image(b.file("_comp_light.exr")), dir = read_image(b.file("_comp_dir.png"));
  const double rt_err = worst_over(w, 8, 7, [&](size_t i, int c, const double* n) {
    const double d3[3] = {stored(dir, i, 0) - 0.5, stored(dir, i, 1) - 0.5, stored(dir, i, 2) - 0.5};
    const double rebalance = std::max(1e-4, double(stored(dir, i, 3)));
    const double unity = stored(light, i, c) * (dot3(n, d3) + 0.5) / rebalance;
    return std::fabs(readback_e_over_pi(sh, i, c, n) - unity) / (stored(light, i, c) / rebalance + 1e-6);
  });
  // Against the source: E/π along the geometric normal per colour (what the encoder kept), and the
  // luminance's L1 direction.
  double normal_err = 0, dir_err = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!w.tangent.coverage[i]) continue;
    const double* ng = &w.frame[i][6];
    for (int c = 0; c < 3; ++c) {
      const double src = source_e_over_pi(w, i, c, ng);
      normal_err = std::max(normal_err, std::fabs(readback_e_over_pi(sh, i, c, ng) - src) / src);
    }
    const auto got = l1_of([&](const double* n) { return readback_luma(sh, i, n); });
    const auto want = l1_of([&](const double* n) { return source_luma(w, i, n); });
    // The colours share dir, so the read-back's direction is dir − 0.5; 8-bit rounding moves each
    // axis by ≤ 0.5/255, turning it by ≤ asin(√3·(0.5/255)/|dir − 0.5|).
    const std::array<double, 3> d3{stored(dir, i, 0) - 0.5, stored(dir, i, 1) - 0.5, stored(dir, i, 2) - 0.5};
    const double bound = std::asin(std::min(1.0, std::sqrt(3.0) * 0.5 / 255 / std::sqrt(dot3(d3.data(), d3.data()))));
    dir_err = std::max(dir_err, angle_between(got, want) / bound);
  }
  std::printf("unity-directional: vs Unity's DecodeDirectionalLightmap %.2e; along the normal vs source %.2e; "
              "L1 direction error %.2f of the 8-bit bound\n", rt_err, normal_err, dir_err);
  EXPECT_LT(rt_err, 1e-5);
  EXPECT_LT(normal_err, std::ldexp(1.0, -11) * 1.01);  // the half colour; w and dir are exact 8-bit values
  EXPECT_LT(dir_err, 1.0);
}

TEST(Presets, MultiLayerAndMultiPartExrL1AndL2AreExact) {
  const fs::path d = ahd_test::temp_dir("presets_exr");
  for (const int coeffs : {4, 9}) {
    BakerOptions bo;
    bo.width = bo.height = N;
    bo.coeffs = coeffs;
    const ShImage src = bake_analytic_scene(bo);
    const std::string band = coeffs == 4 ? "l1" : "l2";
    write_exr_layers((d / ("layers_" + band + ".exr")).string(), src);
    write_exr_parts((d / ("parts_" + band + ".exr")).string(), src);
    const ShImage layers = read_layout(load_layout("exr-layers-" + band), (d / ("layers_" + band)).string(), "");
    EXPECT_EQ(layers.data, src.data) << band;
    EXPECT_EQ(layers.coverage, src.coverage) << band;
    LayoutPreset parts = load_layout("exr-parts-" + band);
    EXPECT_EQ(read_layout(parts, (d / ("parts_" + band)).string(), "").data, src.data) << band;
    // The same parts named by index instead of by name.
    for (size_t k = 0; k < parts.files.size(); ++k) parts.files[k].part_name.clear(), parts.files[k].part = int(k);
    EXPECT_EQ(read_layout(parts, (d / ("parts_" + band)).string(), "").data, src.data) << band;
  }
  fs::remove_all(d);
}

TEST(Presets, BadInputsGiveOneClearErrorBeforeAnyDecode) {
  const WorldBake b("presets_bad");
  const fs::path& d = b.dir;
  const WorldScene& w = b.w;
  const std::string& n = b.normals;
  const LayoutPreset rgba = load_layout("three-rgba"), unity = load_layout("unity-directional");

  // Headers first: a file whose pixels cannot be decoded is not read before a later file is missing.
  write_three_rgba(w, b.base());
  const fs::path r = b.file("_r.exr");
  fs::resize_file(r, fs::file_size(r) - 64);
  EXPECT_THROW(read_image(r.string()), Error);  // the truncated file does fail to decode
  fs::remove(b.file("_b.exr"));
  expect_error([&] { read_layout(rgba, b.base(), n); }, "lm_b.exr: file not found");
  write_image(b.file("_b.exr"), ImageF(N, N / 2, 4), true);
  expect_error([&] { read_layout(rgba, b.base(), n); }, "lm_b.exr: layer size 16x8 differs from the set's 16x16");

  // Parts and layers the file lacks.
  BakerOptions bo;
  bo.width = bo.height = N;
  bo.coeffs = 4;
  const ShImage l1 = bake_analytic_scene(bo);
  write_exr_parts((d / "p.exr").string(), l1);
  write_exr_layers((d / "l.exr").string(), l1);
  expect_error([&] { read_layout(load_layout("exr-parts-l2"), (d / "p").string(), ""); },
               "p.exr: no part named 'L2m2' (parts: L0, L1m1, L10, L1p1)");
  LayoutPreset by_index = load_layout("exr-parts-l1");
  by_index.files[3].part_name.clear(), by_index.files[3].part = 7;
  expect_error([&] { read_layout(by_index, (d / "p").string(), ""); }, "p.exr: no part 7 (the file has 4)");
  expect_error([&] { read_layout(load_layout("exr-layers-l2"), (d / "l").string(), ""); }, "l.exr: no channel L2m2.R");

  // Unity: a direction file without the rebalancing alpha; a colour file that is 8-bit.
  write_unity_directional(w, (d / "u").string());
  write_image((d / "v_comp_light.exr").string(), ImageF(N, N, 3), true);
  write_image((d / "v_comp_dir.png").string(), ImageF(N, N, 3));
  expect_error([&] { read_layout(unity, (d / "v").string(), n); }, "v_comp_dir.png: no channel A");
  LayoutPreset ldr = unity;
  ldr.files[0].pattern = "{base}_comp_dir.png";
  expect_error([&] { read_layout(ldr, (d / "u").string(), n); }, "u_comp_dir.png: 8-bit data");
}

TEST(Presets, SchemaMistakesAreNamed) {
  const fs::path d = ahd_test::temp_dir("presets_schema");
  auto preset_with = [&](const std::string& coefficient) {
    const std::string path = (d / "p.json").string();
    std::ofstream(path) << R"({"name": "p", "coeffs": 4, "files": [{"pattern": "{base}.exr"}], "coefficients": [)"
                        << coefficient << "]}";
    return path;
  };
  expect_error([&] { load_layout(preset_with(R"({"sources": [{"file": 0, "channel": "R"}]})")); },
               "sources must list 3 sources");
  expect_error([&] { load_layout(preset_with(R"({"file": 0, "sources": []})")); }, "either sources or file");
  expect_error([&] { load_layout(preset_with(R"({"file": 0, "divide_by": {"file": 2, "channel": "A"}})")); },
               "names a file that does not exist");
  expect_error([&] { load_layout(preset_with(R"({"sources": [{"file": 0}, {"file": 0}, {"file": 0}]})")); },
               "malformed layout");
  fs::remove_all(d);
}

TEST(Presets, EveryPresetLoadsUnderItsOwnName) {
  const std::vector<std::string> names = list_layouts();
  for (const char* want : {"three-rgba", "bakery-monosh", "unity-directional", "exr-layers-l1", "exr-layers-l2",
                           "exr-parts-l1", "exr-parts-l2"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  for (const std::string& name : names) EXPECT_EQ(load_layout(name).name, name);
}

TEST(Presets, PlainRgbmWithinEightBitPrecision) {
  // RGBM (8-bit RGBA, E/π = rgb·a·8): m rounded up so that rgb ≤ 1, rgb to the nearest 8-bit step.
  const fs::path d = ahd_test::temp_dir("preset_rgbm");
  ImageF src(8, 8, 3), rgbm(8, 8, 4);
  for (size_t i = 0; i < src.texels(); ++i) {
    float peak = 0;
    for (int c = 0; c < 3; ++c) {
      src.data[i * 3 + size_t(c)] = 0.02f + 0.37f * float((i * 7 + size_t(c) * 3) % 19);  // 0.02 … 6.68
      peak = std::max(peak, src.data[i * 3 + size_t(c)]);
    }
    const float m = std::ceil(peak / 8 * 255) / 255;
    rgbm.data[i * 4 + 3] = m;
    for (int c = 0; c < 3; ++c) rgbm.data[i * 4 + size_t(c)] = std::round(src.data[i * 3 + size_t(c)] / (8 * m) * 255) / 255;
  }
  write_image((d / "lm.png").string(), rgbm);
  const ShImage sh = read_layout(load_layout("plain-rgbm"), (d / "lm").string(), "");
  double worst = 0;
  const double z[3] = {0, 0, 1};
  for (size_t i = 0; i < sh.texels(); ++i) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const double m = rgbm.data[i * 4 + 3];
    for (int c = 0; c < 3; ++c)  // in units of the texel's RGBM step 8·m/255
      worst = std::max(worst, std::fabs(eval_irradiance(p[c], z) / kPi - src.data[i * 3 + size_t(c)]) / (8 * m / 255));
  }
  std::printf("plain-rgbm: read-back within %.3f of an 8-bit RGBM step\n", worst);
  EXPECT_LE(worst, 0.5 + 1e-3);  // rounding to the nearest step
  // The alpha the preset multiplies by must exist: an RGB file is refused by name.
  write_image((d / "rgb.png").string(), src);
  expect_error([&] { read_layout(load_layout("plain-rgbm"), (d / "rgb").string(), ""); }, "no channel A");
  fs::remove_all(d);
}

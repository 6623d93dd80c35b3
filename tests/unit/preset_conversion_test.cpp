// Every preset converts to the same AHD lighting as the canonical input: the analytic scene written
// in each baker's exact layout and encoding, read through the preset and converted, against the
// same scene given as the tool's own canonical SH (world space + normals, or tangent space) and
// converted. Compared on what an engine sees — the decoded irradiance for random normals — within
// the bound of the preset's storage (the bound its read-back test states), and bit for bit where
// the storage is exact.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>

#include "files/profile_file.h"
#include "fit/ahd_decode.h"
#include "layout_test_scene.h"
#include "pipeline/convert.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

// The scene in world space as the canonical reader would give it (normals attached).
ShImage canonical_world(const WorldScene& w) {
  ShImage sh = make_sh_image(N, N, 4);
  sh.coverage = w.tangent.coverage;
  sh.normals.resize(sh.texels() * 3);
  for (size_t i = 0; i < sh.texels(); ++i) {
    for (int c = 0; c < 3; ++c) {
      double l0, l1[3];
      world_linear(w, i, c, &l0, l1);
      const double coeff[4] = {l0 / kY00, 1.5 * l1[1] / kY1, 1.5 * l1[2] / kY1, 1.5 * l1[0] / kY1};
      for (int k = 0; k < 4; ++k) sh.texel(i)[k * 3 + c] = float(coeff[k]);
    }
    for (int a = 0; a < 3; ++a) sh.normals[i * 3 + size_t(a)] = w.normals.data[i * 3 + size_t(a)];
  }
  return sh;
}

// The linear fit: smooth in the SH, so a storage difference moves it by a bounded amount (the
// refined fit, the conversion's default, chooses d on a window and may turn further).
PipelineResult convert_planes(const ShImage& sh) {
  PipelineOptions opt;
  opt.fit.direction_fit = DirectionFit::Linear;
  opt.measure = Measure::Off;
  opt.direction = DirectionPlanes::Keep;
  return run_conversion(sh, load_profile("uncompressed"), opt);
}

// The fitted AHD of level 0 before quantisation, as plane values.
DecodedPlanes fitted_planes(const ShImage& sh) {
  PipelineOptions opt;
  opt.fit.direction_fit = DirectionFit::Linear;
  opt.measure = Measure::Off;
  PipelineResult r;
  const auto lv = fit_levels(sh, opt, &r);
  DecodedPlanes p;
  p.width = sh.width, p.height = sh.height;
  for (size_t i = 0; i < lv[0].ahd.size(); ++i) {
    const AhdFit t = lv[0].ahd.texel(i);
    for (int c = 0; c < 3; ++c) p.iz.push_back(t.iz[c]), p.d.push_back(t.d[c]), p.ratio.push_back(t.ratio[c]);
  }
  return p;
}

// E/π that the decoded planes of `r` give at texel i for WORLD direction n (world-space input) —
// rotated into the texel's frame as a decoder does — per colour.
void decoded_e_over_pi(const ShImage& sh, const DecodedPlanes& p, size_t i, const double n[3], double out[3]) {
  double local[3] = {n[0], n[1], n[2]};
  if (!sh.normals.empty()) {
    double R[3][3];
    const double nn[3] = {sh.normals[i * 3], sh.normals[i * 3 + 1], sh.normals[i * 3 + 2]};
    frame_from_normal(nn, R);
    for (int a = 0; a < 3; ++a) local[a] = R[a][0] * n[0] + R[a][1] * n[1] + R[a][2] * n[2];
  }
  decode_irradiance(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], local, 0.05, out);
  for (int c = 0; c < 3; ++c) out[c] /= kPi;
}

// Worst |preset − canonical| of the fitted AHD's E/π over covered texels × random normals, relative
// to the texel's L0 (per colour, or of the colour sum with `luma`).
double worst_difference(const WorldScene& w, const ShImage& preset_sh, const ShImage& ref_sh, bool luma) {
  const DecodedPlanes a = fitted_planes(preset_sh), b = fitted_planes(ref_sh);
  std::mt19937 rng(11);
  double worst = 0;
  for (size_t i = 0; i < preset_sh.texels(); ++i) {
    if (!w.tangent.coverage[i]) continue;
    double l0[3], l1[3], lsum = 0;
    for (int c = 0; c < 3; ++c) world_linear(w, i, c, &l0[c], l1), lsum += l0[c];
    for (const auto& n : directions(w, i, 8, rng)) {
      double ea[3], eb[3];
      decoded_e_over_pi(preset_sh, a, i, n.data(), ea);
      decoded_e_over_pi(ref_sh, b, i, n.data(), eb);
      if (luma) worst = std::max(worst, std::fabs(ea[0] + ea[1] + ea[2] - eb[0] - eb[1] - eb[2]) / (lsum + 1e-6));
      else
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(ea[c] - eb[c]) / (l0[c] + 1e-6));
    }
  }
  return worst;
}

// Largest difference, in codes, between the 8-bit planes (dir, ratio) of two conversions.
int worst_code_step(const PipelineResult& a, const PipelineResult& b, const std::vector<uint8_t>& coverage) {
  int worst = 0;
  for (size_t p = 1; p < a.planes.size(); ++p) {
    const std::vector<uint8_t>& da = a.planes[p].texture.levels[0].data;
    const std::vector<uint8_t>& db = b.planes[p].texture.levels[0].data;
    const size_t per = da.size() / coverage.size();
    for (size_t i = 0; i < coverage.size(); ++i)
      for (size_t k = 0; coverage[i] && k < per; ++k) worst = std::max(worst, std::abs(int(da[i * per + k]) - int(db[i * per + k])));
  }
  return worst;
}

struct WorldCase {
  const char* preset;
  std::function<void(const WorldBake&)> write;
  double bound;  // the read-back bound of the preset's storage (its layout test)
  bool luma;     // compare the colour sum (one shared L1: MonoSH)
};

}  // namespace

TEST(PresetConversion, WorldPresetsMatchTheCanonicalConversion) {
  const WorldCase cases[] = {
      {"godot4-packed", [](const WorldBake& b) { write_godot_packed(b.w, b.file(".exr")); }, 4e-3, false},
      {"bakery-sh", [](const WorldBake& b) { write_bakery_sh(b.w, b.base()); }, 0.035, false},
      {"bakery-monosh", [](const WorldBake& b) { write_bakery_monosh(b.w, b.base()); }, 0.084, true},
      {"three-rgba", [](const WorldBake& b) { write_three_rgba(b.w, b.base()); }, 1.5e-3, false},
  };
  for (const WorldCase& c : cases) {
    const WorldBake b(std::string("pconv_") + c.preset);
    c.write(b);
    const ShImage got = b.read(c.preset), ref = canonical_world(b.w);
    const double worst = worst_difference(b.w, got, ref, c.luma);
    std::printf("%s: fitted AHD vs the canonical conversion's %.2e of L0 (storage bound %.2e)\n", c.preset, worst, c.bound);
    // The fit is smooth in the SH: measured amplification ≤ 1.35 of the storage difference.
    EXPECT_LT(worst, 1.5 * c.bound) << c.preset;
    if (c.luma) continue;  // one shared L1 is not the source's per-colour L1: no plane-level identity
    // Quantised: the same 8-bit codes or a neighbour (a storage difference may cross a rounding edge).
    const int step = worst_code_step(convert_planes(got), convert_planes(ref), b.w.tangent.coverage);
    std::printf("%s: dir/ratio codes within %d of the canonical conversion's\n", c.preset, step);
    EXPECT_LE(step, 1) << c.preset;
  }
}

TEST(PresetConversion, ExactStoragePresetsConvertBitForBit) {
  BakerOptions bo;
  bo.width = bo.height = N;
  for (int coeffs : {4, 9}) {
    bo.coeffs = coeffs;
    const ShImage src = bake_analytic_scene(bo);
    const fs::path d = ahd_test::temp_dir("pconv_exact");
    write_exr_layers((d / "layers.exr").string(), src);
    write_exr_parts((d / "parts.exr").string(), src);
    for (int k = 0; k < coeffs; ++k) write_image((d / ("pc_sh" + std::to_string(k) + ".exr")).string(), coefficient_image(src, k));
    const std::string level = coeffs == 4 ? "l1" : "l2";
    std::vector<std::pair<std::string, std::string>> presets = {{"exr-layers-" + level, "layers"},
                                                                 {"exr-parts-" + level, "parts"}};
    if (coeffs == 9) presets.push_back({"per-coefficient", "pc"});  // its preset names all nine files
    const PipelineResult ref = convert_planes(src);
    for (const auto& [preset, base] : presets) {
      const PipelineResult got = convert_planes(read_layout(load_layout(preset), (d / base).string(), ""));
      ASSERT_EQ(got.planes.size(), ref.planes.size()) << preset;
      for (size_t p = 0; p < ref.planes.size(); ++p)
        EXPECT_TRUE(got.planes[p].texture.levels[0].data == ref.planes[p].texture.levels[0].data)
            << preset << " L" << (coeffs == 4 ? 1 : 2) << " plane " << ref.planes[p].name;
    }
    fs::remove_all(d);
  }
}

TEST(PresetConversion, UnityAndPlainKeepTheIrradianceAlongTheNormal) {
  // Unity's form cannot hold the full L1 (|L1| ≤ L0 per axis) and a plain map has none: what they
  // must convert exactly is I_z, the irradiance along the surface normal.
  const WorldBake b("pconv_unity");
  write_unity_directional(b.w, b.base());
  const PipelineResult u = convert_planes(b.read("unity-directional"));
  const PipelineResult ref = convert_planes(canonical_world(b.w));
  const ImageF iu = decode_plane(u.planes[0].texture.format, u.planes[0].texture.levels[0]);
  const ImageF ir = decode_plane(ref.planes[0].texture.format, ref.planes[0].texture.levels[0]);
  double worst = 0;
  for (size_t i = 0; i < iu.texels(); ++i)
    if (b.w.tangent.coverage[i])
      for (int c = 0; c < 3; ++c) {
        double l0, l1[3];
        world_linear(b.w, i, c, &l0, l1);
        worst = std::max(worst, std::fabs(iu.data[i * 4 + size_t(c)] - ir.data[i * 4 + size_t(c)]) / (kPi * l0 + 1e-6));
      }
  std::printf("unity-directional: I_z plane vs the canonical conversion %.2e of L0\n", worst);
  EXPECT_LT(worst, 3e-3);  // half storage of the light (2^-11) and the 8-bit direction's half-Lambert

  // Plain: E/π along the normal only. Converted, the I_z plane of the same scene without its
  // directional part (and nothing else: the direction planes are dropped).
  ImageF plain(N, N, 3);
  ShImage ambient = canonical_world(b.w);
  ambient.normals.clear();
  for (size_t i = 0; i < ambient.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      plain.data[i * 3 + size_t(c)] = float(kY00 * ambient.texel(i)[c]);
      for (int k = 1; k < 4; ++k) ambient.texel(i)[k * 3 + c] = 0;
    }
  write_image(b.file("_plain.exr"), plain);
  PipelineOptions opt;
  opt.measure = Measure::Off;
  const PipelineResult p =
      run_conversion(read_layout(load_layout("plain"), b.file("_plain"), ""), load_profile("uncompressed"), opt);
  const PipelineResult pr = convert_planes(ambient);
  ASSERT_EQ(p.planes.size(), 1u);
  const ImageF ip = decode_plane(p.planes[0].texture.format, p.planes[0].texture.levels[0]);
  const ImageF ipr = decode_plane(pr.planes[0].texture.format, pr.planes[0].texture.levels[0]);
  double worst_plain = 0;
  for (size_t i = 0; i < ip.texels(); ++i)
    if (b.w.tangent.coverage[i])
      for (int c = 0; c < 3; ++c)
        worst_plain = std::max(worst_plain, std::fabs(ip.data[i * 4 + size_t(c)] - ipr.data[i * 4 + size_t(c)]) /
                                                 (std::fabs(ipr.data[i * 4 + size_t(c)]) + 1e-6));
  std::printf("plain: I_z plane vs the canonical conversion %.2e (relative)\n", worst_plain);
  EXPECT_LT(worst_plain, 1e-3);  // float E/π vs float coefficients, one half-float rounding
}

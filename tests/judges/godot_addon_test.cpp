// GodotAddon.*: Godot 4.6 itself consumes ahdpack's files through the add-on addons/ahdpack.
// tests/tools/godot/run_godot.mjs runs the project docs/examples/godot/render_check (Godot's official
// web build in headless Chromium, Compatibility renderer on SwiftShader) packed with the add-on,
// check.json and conversions of the built-in sample (profiles `pc-bc` and `uncompressed`, KTX2 and
// DDS; `packed-rgb9e5`, KTX2) and of a two-page Godot atlas (array KTX2, `pc-bc` and zstd `uncompressed`). The add-on loads
// the planes with Godot's own Image.load_ktx_from_buffer / load_dds_from_buffer (array and zstd
// files and RGBA8 with its own KTX2 reader) into Texture2DArray, and its ahd_lightmap.gdshader lights a quad:
// flat and normal-mapped normals, a sub-rectangle of the atlas, mip level 1, the world-space frame,
// each page. Every pixel's float32 E comes back exactly (the shader's AHD_READBACK hook, 7 bits per
// render through Godot's 8-bit sRGB output, mapped back with a calibration ramp) and must equal the
// reference decoder (decode_planes + decode_irradiance) for the same normal.
// Skipped with the reason when chromium, node or the npm package is missing (scripts/setup.sh).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>

#include "cli_runner.h"
#include "godot_run.h"
#include "layout_test_scene.h"
#include "codecs/octahedral.h"
#include "core/texture.h"
#include "files/manifest_file.h"
#include "fit/ahd_decode.h"
#include "pipeline/plane_decode.h"
#include "sh/sh.h"
#include "test_data.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

std::vector<unsigned char> read_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The reference decoder's planes of a conversion at `level` and `layer`, as `ahdpack decode` reads them.
ahd::DecodedPlanes reference_planes(const std::string& manifest, int level, int layer, ahd::Manifest* m) {
  *m = ahd::read_manifest_file(manifest);
  std::vector<ahd::Plane> planes;
  for (const auto& mp : m->planes)
    planes.push_back({mp.name, ahd::texture_layer(ahd::read_manifest_plane(manifest, mp), uint32_t(layer))});
  return ahd::decode_planes(planes, m->ratio_form == ahd::RatioForm::Rgb, level);
}

// The float32 values the AHD_READBACK hook wrote for pixel i (w x h pixels, 5 renders of RGBA8,
// 7 bits each), through `back` (the calibration ramp: byte read back -> digit written).
void read_floats(const std::vector<unsigned char>& px, const int back[256], size_t i, size_t pixels, float out[3]) {
  for (int ch = 0; ch < 3; ++ch) {
    uint32_t bits = 0;
    for (int r = 0; r < 5; ++r) {
      const int v = back[px[size_t(r) * pixels * 4 + i * 4 + ch]];
      if (v < 0) throw std::runtime_error("a byte the calibration ramp never gave");
      bits |= uint32_t(v) << (7 * r);
    }
    std::memcpy(&out[ch], &bits, 4);
  }
}

// A two-page Godot 4 packed atlas (L0, L1y, L1z, L1x stacked per page, t = L1/(8 L0) + 0.5) of the
// layout tests' world scene; page 1 is darker and less directional, so the pages differ.
void write_two_page_atlas(const layout_test::WorldScene& w, const std::string& path) {
  const int n = layout_test::N;
  ahd::ImageF img(n, 8 * n, 3);
  for (int p = 0; p < 2; ++p)
    for (size_t i = 0; i < w.tangent.texels(); ++i) {
      const int x = int(i % n), y = int(i / n) + 4 * n * p;
      for (int c = 0; c < 3; ++c) {
        double l0, l1[3];
        layout_test::world_linear(w, i, c, &l0, l1);
        if (p == 1) l0 *= 0.6, l1[0] *= 0.3, l1[1] *= 0.3, l1[2] *= 0.3;
        img.at(x, y)[c] = float(l0);
        const double yzx[3] = {l1[1], l1[2], l1[0]};
        for (int k = 0; k < 3; ++k)
          img.at(x, y + (k + 1) * n)[c] = l0 > 0 ? float(std::clamp(yzx[k] / (8 * l0) + 0.5, 0.0, 1.0)) : 0.5f;
      }
    }
  ahd::write_image(path, img, /*half=*/true, {"R", "G", "B"});
}

}  // namespace

TEST(GodotAddon, KtxPlanesLitInGodotMatchTheReferenceDecoder) {
  if (const std::string why = ahd_test::godot_missing(); !why.empty()) GTEST_SKIP() << why;

  const fs::path dir = ahd_test::temp_dir("godot_addon");
  const fs::path src = dir / "s.exr";
  ASSERT_EQ(run_cli({"sample", "-o", src.string(), "--size", "32"}).exit_code, 0);
  // {profile, container}; packed-rgb9e5: E5B9G9R9 + the RGBA8 dirratio (which Godot's KTX loader
  // does not map: the add-on reads it).
  const std::vector<std::array<std::string, 2>> profiles = {{"pc-bc", "ktx2"},
                                                            {"pc-bc", "dds"},
                                                            {"uncompressed", "ktx2"},
                                                            {"uncompressed", "dds"},
                                                            {"packed-rgb9e5", "ktx2"}};
  // Two-page atlases (array planes, which Godot's KTX loader refuses: the add-on reads them), one
  // zstd-supercompressed: {id, profile, --zstd}.
  const std::vector<std::array<std::string, 3>> atlases = {{"atlas-pc-bc", "pc-bc", ""},
                                                           {"atlas-uncompressed-zstd", "uncompressed", "--zstd"}};
  const layout_test::WorldBake bake("godot_addon_atlas");
  const std::string atlas = (dir / "World.exr").string();
  write_two_page_atlas(bake.w, atlas);
  ahd_test::GodotFiles files;
  nlohmann::json check = {{"runs", nlohmann::json::array()}};
  // Each profile as KTX2 (id = the profile) and as DDS (id PROFILE-dds).
  for (const auto& [p, ext] : profiles) {
    const std::string id = ext == "dds" ? p + "-dds" : p;
    const fs::path out = dir / "conv" / id / ("s." + ext);
    const auto r = run_cli({"convert", src.string(), "-o", out.string(), "--profile", p});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    check["runs"].push_back({{"id", id}, {"manifest", "res://conv/" + id + "/s.json"}});
    files.add_conversion(out.parent_path(), "s", "conv/" + id, "." + ext);
  }
  for (const auto& [id, profile, zstd] : atlases) {
    const fs::path out = dir / "conv" / id / "s.ktx2";
    std::vector<std::string> args = {"convert", atlas,        "--layout",   "godot4-packed", "--pages",
                                     "2",       "--normals",  bake.normals, "--direction",   "keep",
                                     "-o",      out.string(), "--profile",  profile};
    if (!zstd.empty()) args.push_back(zstd);
    const auto r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    check["runs"].push_back({{"id", id}, {"manifest", "res://conv/" + id + "/s.json"}, {"pages", 2}});
    files.add_conversion(out.parent_path(), "s", "conv/" + id);
  }
  std::ofstream(dir / "check.json") << check.dump();
  files.add(dir / "check.json", "check.json");
  files.add_addon();  // as a project has it: res://addons/ahdpack/
  const std::string log = ahd_test::run_godot("render_check", files, dir / "out");
  ASSERT_TRUE(fs::exists(dir / "out" / "report.json")) << "run_godot.mjs gave no report:\n" << log;
  const nlohmann::json rep = nlohmann::json::parse(std::ifstream(dir / "out" / "report.json"));
  ASSERT_TRUE(rep["bptc"].get<bool>() && rep["rgtc"].get<bool>()) << "this renderer lacks BPTC or RGTC: " << rep.dump();

  // The calibration ramp: k/255 written (k = 0..255) -> the byte read back. Godot's output is
  // injective from k = 8 on; the hook writes digits as 8..135.
  const auto ramp = read_bytes(dir / "out" / "ramp.bin");
  ASSERT_EQ(ramp.size(), 256u * 4);
  int back[256];
  std::fill(back, back + 256, -1);
  for (int k = 8; k < 136; ++k) {
    const int b = ramp[size_t(k) * 4];
    EXPECT_EQ(back[b], -1) << "bytes " << back[b] << " and " << k << " both come back as " << b;
    back[b] = k - 8;
  }

  // First the dir and ratio planes as the shader samples them (cases planesP, page P, level 0):
  // R8/RG8/RGBA8 exactly our decoder's k/255. A GPU decodes BC4/BC5 to 8 bits, and SwiftShader does not
  // simply round the palette value down or to nearest (measured: (6 c0 + c1)/7 = 108.857 comes back
  // 109, 127.714 comes back 127): each value must lie within one 8-bit step of our exact palette
  // value, and the lit cases below then decode with the values Godot sampled.
  // Then E, relative to max(|reference|, 1) per channel: BC6H, RGBA16F and E5B9G9R9 reach the shader as the
  // values our decoder gives (texel centres, no blend between texels), so what is left is float32
  // arithmetic (the shader) against double (the reference): 2e-6 flat, and the normal map's
  // normalisation and sqrt: 1e-5; the world-space case adds Godot's 16-bit octahedral vertex
  // normals and tangents ((0,0,1) is stored as (-1.5e-5, -1.5e-5, 1)) and the view/world
  // matrices: 1e-4. For pc-bc the difference the 8-bit RGTC decode makes against the exact
  // palette is printed (it is not an error of the add-on).
  // The world case's turn R (columns, as Godot's Basis holds them: turn[k] = R e_k).
  double turn[3][3];
  for (int k = 0; k < 9; ++k) turn[k / 3][k % 3] = rep["world_turn"][k].get<double>();
  size_t runs_seen = 0;
  for (const auto& run : rep["runs"]) {
    const std::string id = run["id"];
    const bool bc = id.find("pc-bc") != std::string::npos, array = id.rfind("atlas", 0) == 0;
    ++runs_seen;
    const fs::path manifest = dir / "conv" / id / "s.json";
    // What Godot's loader made of each plane (Image.Format): the traps the add-on handles.
    EXPECT_EQ(run["layers"].get<int>(), array ? 2 : 1) << id;
    if (bc) {
      EXPECT_EQ(run["formats"]["iz"].get<int>(), 24) << "FORMAT_BPTC_RGBFU";
      EXPECT_EQ(run["formats"]["dir"].get<int>(), 21) << "FORMAT_RGTC_RG";
      EXPECT_EQ(run["formats"]["ratio"].get<int>(), 20) << "FORMAT_RGTC_R";
    } else if (array) {  // read by the add-on itself: R8 and RG8 stay R8 and RG8
      EXPECT_EQ(run["formats"]["iz"].get<int>(), 15) << "FORMAT_RGBAH";
      EXPECT_EQ(run["formats"]["dir"].get<int>(), 3) << "FORMAT_RG8";
      EXPECT_EQ(run["formats"]["ratio"].get<int>(), 2) << "FORMAT_R8";
    } else if (id == "packed-rgb9e5") {
      EXPECT_EQ(run["formats"]["iz"].get<int>(), 16) << "FORMAT_RGBE9995";
      EXPECT_EQ(run["formats"]["dirratio"].get<int>(), 5) << "FORMAT_RGBA8 (the add-on's KTX2 reader)";
    } else {  // Godot's KTX and DDS loaders alike
      EXPECT_EQ(run["formats"]["iz"].get<int>(), 15) << "FORMAT_RGBAH";
      EXPECT_EQ(run["formats"]["dir"].get<int>(), 1) << "FORMAT_LA8: an RG8 plane";
      EXPECT_EQ(run["formats"]["ratio"].get<int>(), 0) << "FORMAT_L8: an R8 plane";
    }
    EXPECT_EQ(run["iz_mips"].get<int>(), array ? 4 : 5) << id << ": the file's mips (down to 1x1)";
    const auto normal = read_bytes(dir / "out" / (id + ".normal.bin"));
    // The sampled (dir x, dir y, ratio) of each page at level 0.
    std::map<int, std::vector<float>> sampled;
    for (const auto& c : run["cases"]) {
      const std::string name = c["name"];
      if (name.rfind("planes", 0) != 0) continue;
      const int w = c["width"], h = c["height"], layer = c["page"];
      const auto px = read_bytes(dir / "out" / (id + "." + name + ".bin"));
      ASSERT_EQ(px.size(), size_t(w) * h * 4 * 5) << id << " " << name;
      ahd::Manifest m;
      const ahd::DecodedPlanes ref = reference_planes(manifest.string(), 0, layer, &m);
      ASSERT_EQ(ref.width, w);
      ASSERT_EQ(ref.height, h);
      std::vector<float>& v = sampled[layer];
      v.resize(size_t(w) * h * 3);
      double worst = 0;
      size_t bad = 0;
      for (size_t i = 0; i < size_t(w) * h; ++i) {
        read_floats(px, back, i, size_t(w) * h, &v[i * 3]);
        double uv[2];
        const double dd[3] = {ref.d[i * 3], ref.d[i * 3 + 1], ref.d[i * 3 + 2]};
        ahd::hemi_oct_encode(dd, uv);
        const double want[3] = {uv[0] * 0.5 + 0.5, uv[1] * 0.5 + 0.5, ref.ratio[i * 3]};
        for (int ch = 0; ch < 3; ++ch) {
          const double steps = std::fabs(v[i * 3 + ch] - want[ch]) * 255;
          worst = std::max(worst, steps);
          if (steps > (bc ? 0.9999 : 1e-4) && bad++ < 5)
            ADD_FAILURE() << id << " " << name << " texel " << i << " channel " << ch << ": Godot samples "
                          << v[i * 3 + ch] * 255 << "/255, our decoder gives " << want[ch] * 255 << "/255";
        }
      }
      std::printf("%-23s %-6s %2dx%-2d: dir and ratio as sampled, worst %.3f 8-bit steps from our decoder\n",
                  id.c_str(), name.c_str(), w, h, worst);
      EXPECT_EQ(bad, 0u);
    }
    ASSERT_EQ(sampled.size(), size_t(run["layers"].get<int>())) << id;
    for (const auto& c : run["cases"]) {
      const std::string name = c["name"];
      if (name.rfind("planes", 0) == 0) continue;
      const int w = c["width"], h = c["height"];
      const bool detail = c["normal_map"], world = c["world_frame"];
      ASSERT_EQ(c["image_format"].get<int>(), 5) << "RGBA8";
      const auto px = read_bytes(dir / "out" / (id + "." + name + ".bin"));
      ASSERT_EQ(px.size(), size_t(w) * h * 4 * 5) << id << " " << name;
      ahd::Manifest m;
      const int level = name == "level1" ? 1 : 0, layer = c["page"];
      const ahd::DecodedPlanes ref = reference_planes(manifest.string(), level, layer, &m);
      // The case's pixel (x, y) is the reference texel (x0 + x, y0 + y): the rect case shows the
      // atlas rectangle (0.25, 0.5, 0.5, 0.5) of level 0 at one pixel per texel.
      const int x0 = name == "rect" ? ref.width / 4 : 0, y0 = name == "rect" ? ref.height / 2 : 0;
      ASSERT_LE(x0 + w, ref.width);
      ASSERT_LE(y0 + h, ref.height);
      double worst = 0, worst_exact = 0;
      size_t bad = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const size_t t = size_t(y0 + y) * ref.width + (x0 + x);
          float d[3], ratio[3];
          std::copy_n(&ref.d[t * 3], 3, d);
          std::copy_n(&ref.ratio[t * 3], 3, ratio);
          if (bc && detail) {  // BC4/BC5 as Godot sampled them (a flat normal gives E = I_z: no need)
            ASSERT_EQ(level, 0);
            const float* g = &sampled[layer][t * 3];
            ahd::unit_uv_to_dir(g, d);
            std::fill(ratio, ratio + 3, g[2]);
          }
          double n[3] = {0, 0, 1};
          if (detail) {  // the normal map as ahd_normal_ts reads it: xy from the texel, z rebuilt
            const size_t k = (size_t(y) * w + x) * 4;
            n[0] = normal[k] / 255.0 * 2 - 1, n[1] = normal[k + 1] / 255.0 * 2 - 1;
            n[2] = std::sqrt(std::max(0.0, 1 - n[0] * n[0] - n[1] * n[1]));
            const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (double& v : n) v /= len;
          }
          if (world) {  // the quad turned by R: ng = R z, the shading normal R n, in the frame of ng
            double nw[3], frame[3][3];
            for (int i = 0; i < 3; ++i) nw[i] = turn[0][i] * n[0] + turn[1][i] * n[1] + turn[2][i] * n[2];
            ahd::frame_from_normal(turn[2], frame);
            for (int i = 0; i < 3; ++i) n[i] = frame[i][0] * nw[0] + frame[i][1] * nw[1] + frame[i][2] * nw[2];
          }
          double e[3], e_exact[3];
          ahd::decode_irradiance(&ref.iz[t * 3], d, ratio, n, m.dz_min, e);
          ahd::decode_irradiance(&ref.iz[t * 3], &ref.d[t * 3], &ref.ratio[t * 3], n, m.dz_min, e_exact);
          float gpu[3];
          read_floats(px, back, size_t(y) * w + x, size_t(w) * h, gpu);
          for (int ch = 0; ch < 3; ++ch) {
            const float g = gpu[ch];
            const double scale = std::max(std::fabs(e[ch]), 1.0), err = std::fabs(g - e[ch]) / scale;
            worst = std::max(worst, err);
            worst_exact = std::max(worst_exact, std::fabs(e[ch] - e_exact[ch]) / scale);
            if (err > (world ? 1e-4 : detail ? 1e-5 : 2e-6) && bad++ < 5)
              ADD_FAILURE() << id << " " << name << " pixel (" << x << "," << y << ") channel " << ch << ": Godot " << g
                            << ", reference " << e[ch];
          }
        }
      std::printf("%-23s %-6s %2dx%-2d: worst relative difference %.2e%s\n", id.c_str(), name.c_str(), w, h, worst,
                  bc && detail
                      ? (" (E from the exact RGTC palette differs by " + std::to_string(worst_exact) + ")").c_str()
                      : "");
      EXPECT_EQ(bad, 0u);
    }
  }
  EXPECT_EQ(runs_seen, profiles.size() + atlases.size());

  // ahd_lightmap_instance.gd on a MeshInstance3D: the material at its rectangle and page, Godot's
  // own lightmap off for it.
  const auto& inst = rep["instance"];
  ASSERT_TRUE(inst["material"].get<bool>()) << inst.dump();
  EXPECT_EQ(inst["gi_mode"], inst["gi_mode_disabled"]);
  EXPECT_EQ(inst["rect"], nlohmann::json({0.25, 0.5, 0.5, 0.25}));
  EXPECT_EQ(inst["page"].get<double>(), 0.0);
  EXPECT_NEAR(inst["dz_min"].get<double>(),
              ahd::read_manifest_file((dir / "conv" / "pc-bc" / "s.json").string()).dz_min, 1e-12);
  EXPECT_EQ(inst["albedo"], nlohmann::json({0.5, 0.25, 1.0}));
  EXPECT_EQ(inst["shader"], "res://addons/ahdpack/ahd_lightmap.gdshader");

  // The shader as a game renders it (no readback hook; lit.bin): flat normal (E = I_z), no ambient
  // light, through Godot's 8-bit output. The albedo Color(1, 0.5, 1) of the source_color uniform
  // reaches the shader as given (0.5) in the Compatibility renderer, which decodes ALBEDO and
  // EMISSION from sRGB with its cubic (drivers/gles3/shaders/scene.glsl); the add-on lights the
  // decoded albedo and writes the emission that cubic maps to albedo_linear E / π, as Godot's own
  // lightmaps light a material. An unshaded ALBEDO k/255 (the calibration ramp) goes through the same
  // decode, so each byte must be the ramp's at k = the cubic's inverse of albedo_linear E / π,
  // within 2 (the value's own 8-bit rounding and the transfer's steps).
  const auto compat_linear = [](double c) { return c * (c * (c * 0.305306011 + 0.682171111) + 0.012522878); };
  const auto compat_encode = [&](double x) {
    double y = std::pow(x, 0.4545);
    for (int i = 0; i < 6; ++i) y -= (compat_linear(y) - x) / (y * (y * 0.915918033 + 1.364342222) + 0.012522878);
    return y;
  };
  const auto& lit = rep["lit"];
  ASSERT_EQ(lit["image_format"].get<int>(), 5) << "RGBA8";
  const auto lit_px = read_bytes(dir / "out" / "lit.bin");
  ahd::Manifest lm;
  const ahd::DecodedPlanes lref = reference_planes((dir / "conv" / "pc-bc" / "s.json").string(), 0, 0, &lm);
  ASSERT_EQ(lit_px.size(), size_t(lref.width) * lref.height * 4);
  const double albedo[3] = {1.0, 0.5, 1.0};
  int worst_lit = 0;
  size_t lit_checked = 0, lit_bad = 0;
  for (size_t i = 0; i < size_t(lref.width) * lref.height; ++i)
    for (int ch = 0; ch < 3; ++ch) {
      const double lin = compat_linear(albedo[ch]) * lref.iz[i * 3 + ch] / 3.14159265358979;
      if (!(lin > 0) || lin > 1) continue;  // clamped
      const double want = compat_encode(lin);
      if (want < 16 / 255.0) continue;  // the ramp's flat foot
      const int expect = ramp[size_t(std::lround(want * 255)) * 4], got = lit_px[i * 4 + ch];
      worst_lit = std::max(worst_lit, std::abs(got - expect));
      ++lit_checked;
      if (std::abs(got - expect) > 2 && lit_bad++ < 5)
        ADD_FAILURE() << "lit texel " << i << " channel " << ch << ": Godot byte " << got << ", expected " << expect
                      << " (albedo_linear E / pi = " << lin << ")";
    }
  std::printf("lit (no hook): %zu values checked, worst %d 8-bit steps\n", lit_checked, worst_lit);
  EXPECT_GT(lit_checked, size_t(lref.width) * lref.height);
  EXPECT_EQ(lit_bad, 0u);
}

// Real bakes as they lie on disk (issue 16): the real Godot 4.2 bake of tests/data/bakes/
// detected and read back against its own layers; a 4-page Godot-style atlas converted to 4-layer
// array planes equal, layer by layer, to each page converted alone; the page count refused when
// unknown; --layout auto over the presets' own file sets.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "files/file_io.h"
#include "files/container_file.h"
#include "bakers/godot/godot_import.h"
#include "bakers/layout_detect.h"
#include "bakers/layout_pages.h"
#include "layout_test_scene.h"
#include "pipeline/manifest.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

const fs::path kVermilion = ahd_test::test_data("bakes/godot42-vermilion");

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

// Page p of a Godot-style atlas: the world scene with page-dependent lighting (L0 scaled, L1 axes
// permuted and signed), so that every page converts to different planes.
void page_linear(const WorldScene& w, size_t i, int c, int page, double* l0, double l1[3]) {
  double a, b[3];
  world_linear(w, i, c, &a, b);
  *l0 = a * (1 + 0.5 * page);
  const int s = page % 3;
  const double sign = page & 1 ? -1 : 1;
  for (int k = 0; k < 3; ++k) l1[k] = sign * b[(k + s) % 3] * (1 + 0.5 * page);
}

// Godot ≥ 4.4 packed atlas: `pages` pages stacked page-major (each: L0, L1y, L1z, L1x), half.
void write_godot_atlas(const WorldScene& w, const std::string& path, int first_page, int pages) {
  ImageF img(N, 4 * N * pages, 3);
  for (int p = 0; p < pages; ++p)
    for (size_t i = 0; i < w.tangent.texels(); ++i) {
      const int x = int(i % N), y = int(i / N) + 4 * N * p;
      for (int c = 0; c < 3; ++c) {
        double l0, l1[3];
        page_linear(w, i, c, first_page + p, &l0, l1);
        img.at(x, y)[c] = float(l0);
        const double yzx[3] = {l1[1], l1[2], l1[0]};
        for (int k = 0; k < 3; ++k)
          img.at(x, y + (k + 1) * N)[c] = l0 > 0 ? float(std::clamp(yzx[k] / (8 * l0) + 0.5, 0.0, 1.0)) : 0.5f;
      }
    }
  write_image(path, img, /*half=*/true, {"R", "G", "B"});
}

void write_import(const std::string& exr, int slices) {
  std::ofstream f(exr + ".import");
  f << "[remap]\n\nimporter=\"2d_array_texture\"\ntype=\"CompressedTexture2DArray\"\n\n[params]\n\n"
       "slices/horizontal=1\nslices/vertical="
    << slices << "\n";
}

void write_project(const fs::path& dir, const std::string& version) {
  std::ofstream f(dir / "project.godot");
  f << "config_version=5\n\n[application]\n\nconfig/features=PackedStringArray(\"" << version << "\", \"Forward Plus\")\n";
}

Manifest read_manifest(const fs::path& p) {
  const std::vector<uint8_t> b = read_file_bytes(p.string());
  return manifest_from_json(std::string(b.begin(), b.end()), p.string());
}

}  // namespace

TEST(Atlas, RealGodot42BakeDetectedAsRawOnePageAndReadBackAgainstItsLayers) {
  AHD_REQUIRE_DATA(kVermilion / "world.exr");
  const std::string exr = (kVermilion / "world.exr").string();
  ASSERT_TRUE(fs::exists(exr)) << exr;
  const LayoutDetection d = detect_layout(exr);
  EXPECT_EQ(d.preset, "godot4-unpacked");
  EXPECT_EQ(d.base, (kVermilion / "world").string());
  std::string why;
  for (const auto& r : d.reasons) why += r + "\n";
  EXPECT_TRUE(contains(why, "slices/vertical=4")) << why;
  EXPECT_TRUE(contains(why, "Godot 4.2")) << why;
  EXPECT_TRUE(contains(why, "negative values")) << why;
  const LayoutPreset layout = load_layout(d.preset);
  const LayoutPages lp = layout_pages(layout, exr, 0);
  EXPECT_EQ(lp.pages, 1);
  EXPECT_TRUE(contains(lp.why, "slices/vertical=4")) << lp.why;

  // Read back (any normal map of the right size; the SH is kept in world space) against the
  // file's own four layers: raw signed radiance SH, layer k = coefficient k, bit for bit.
  const fs::path dir = ahd_test::temp_dir("atlas_vermilion");
  ImageF n(512, 512, 3);
  for (size_t i = 0; i < n.texels(); ++i) n.data[i * 3 + 1] = 1;
  write_image((dir / "n.exr").string(), n);
  const ShImage sh = read_layout(layout, exr, (dir / "n.exr").string());
  ASSERT_EQ(sh.width, 512);
  ASSERT_EQ(sh.height, 512);
  const ImageF raw = read_image(exr);
  ASSERT_EQ(raw.channels, 3);
  size_t compared = 0, differ = 0, nonzero_l1 = 0;
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 512; ++x) {
      const size_t i = size_t(y) * 512 + x;
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c) {
          const float want = raw.at(x, y + 512 * k)[c];  // channels R, G, B as OIIO orders them
          if (!std::isfinite(want)) continue;
          ++compared;
          differ += sh.texel(i)[k * 3 + c] != want;
          nonzero_l1 += k > 0 && want != 0;
        }
    }
  std::printf("vermilion: %zu values compared, %zu differ, %zu non-zero L1\n", compared, differ, nonzero_l1);
  EXPECT_EQ(compared, size_t(512) * 512 * 12);
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(nonzero_l1, size_t(512) * 512);  // real directional data, not an empty bake
  fs::remove_all(dir);
}

TEST(Atlas, RealGodot42BakeConvertsFromTheCommandLineWithTheDetectionPrinted) {
  AHD_REQUIRE_DATA(kVermilion / "world.exr");
  const fs::path dir = ahd_test::temp_dir("atlas_vermilion_cli");
  ImageF n(512, 512, 3);
  for (size_t i = 0; i < n.texels(); ++i) n.data[i * 3 + 1] = 1;
  write_image((dir / "n.exr").string(), n);
  const auto r = ahd_test::run_cli({"convert", (kVermilion / "world.exr").string(), "--normals", (dir / "n.exr").string(), "-o",
                                    (dir / "out" / "world.ktx2").string(), "--levels", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "layout auto: godot4-unpacked")) << r.output;
  EXPECT_TRUE(contains(r.output, "1 page(s) from world.exr.import")) << r.output;
  EXPECT_TRUE(contains(r.output, "project.godot: Godot 4.2")) << r.output;
  const Manifest m = read_manifest(dir / "out" / "world.json");
  EXPECT_EQ(m.width, 512u);
  EXPECT_EQ(m.layers, 1u);
  fs::remove_all(dir);
}

TEST(Atlas, FourPageGodotAtlasConvertsToArrayPlanesEqualToEachPageAlone) {
  const WorldBake b("atlas_pages");
  const fs::path& d = b.dir;
  const std::string atlas = (d / "World.exr").string();
  write_godot_atlas(b.w, atlas, 0, 4);
  write_import(atlas, 16);
  write_project(d, "4.6");
  for (int p = 0; p < 4; ++p) write_godot_atlas(b.w, (d / ("page" + std::to_string(p) + ".exr")).string(), p, 1);

  for (const char* ext : {"ktx2", "dds"}) {
    const std::string e = ext;
    const fs::path out = d / ("out_" + e);
    auto r = ahd_test::run_cli({"convert", atlas, "--normals", b.normals, "-o", (out / ("atlas." + e)).string(), "--direction",
                                "keep"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "layout auto: godot4-packed")) << r.output;
    EXPECT_TRUE(contains(r.output, "4 page(s) from World.exr.import (slices/vertical=16")) << r.output;
    const Manifest m = read_manifest(out / "atlas.json");
    EXPECT_EQ(m.layers, 4u);
    ASSERT_EQ(m.planes.size(), 3u);  // iz, dir, ratio
    for (int p = 0; p < 4; ++p) {
      const std::string page = "page" + std::to_string(p);
      r = ahd_test::run_cli({"convert", (d / (page + ".exr")).string(), "--layout", "godot4-packed", "--normals", b.normals,
                             "-o", (out / (page + "." + e)).string(), "--direction", "keep", "-q"});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      for (const ManifestPlane& mp : m.planes) {
        EXPECT_EQ(mp.layers, 4u);
        const Texture array = read_container_file((out / mp.file).string());
        ASSERT_EQ(array.layers, 4u);
        const Texture alone = read_container_file(ahd_test::plane_file((out / (page + ".json")).string(), mp.name));
        const Texture layer = texture_layer(array, uint32_t(p));
        ASSERT_EQ(layer.levels.size(), alone.levels.size());
        for (size_t l = 0; l < alone.levels.size(); ++l)
          EXPECT_EQ(layer.levels[l].data, alone.levels[l].data) << e << " " << mp.name << " page " << p << " level " << l;
      }
      // decode --layer p of the array = decode of the page alone (KTX2; the DDS bytes are equal above).
      if (e != "ktx2") continue;
      r = ahd_test::run_cli({"decode", (out / "atlas.json").string(), "--layer", std::to_string(p), "-o",
                             (out / ("dec_array" + std::to_string(p) + ".exr")).string()});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      r = ahd_test::run_cli({"decode", (out / (page + ".json")).string(), "-o", (out / ("dec_" + page + ".exr")).string()});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_EQ(read_image((out / ("dec_array" + std::to_string(p) + ".exr")).string()).data,
                read_image((out / ("dec_" + page + ".exr")).string()).data);
    }
    // The pages really differ (a stacked copy of one page would pass the above only by accident).
    const Texture iz = read_container_file(ahd_test::plane_file((out / "atlas.json").string(), "iz"));
    EXPECT_NE(texture_layer(iz, 0).levels[0].data, texture_layer(iz, 3).levels[0].data);
  }
  const auto r = ahd_test::run_cli({"decode", (d / "out_ktx2" / "atlas.json").string(), "--layer", "4", "-o", (d / "x.exr").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "--layer 4 does not exist")) << r.output;
}

TEST(Atlas, UnknownPageCountIsRefusedNamingIt) {
  const WorldBake b("atlas_unknown");
  const fs::path& d = b.dir;
  const std::string atlas = (d / "World.exr").string();
  write_godot_atlas(b.w, atlas, 0, 4);
  // No import file, no --pages: refused, nothing written.
  auto r = ahd_test::run_cli({"convert", atlas, "--layout", "godot4-packed", "--normals", b.normals, "-o", (d / "out" / "a.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "page count unknown")) << r.output;
  EXPECT_TRUE(contains(r.output, "--pages")) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(d / "out"));
  // The library refuses the same (read_layout never mixes pages).
  expect_error([&] { read_layout(load_layout("godot4-packed"), atlas, b.normals); }, "page count unknown");
  // --pages that does not divide the image, and --pages given.
  r = ahd_test::run_cli({"convert", atlas, "--layout", "godot4-packed", "--pages", "3", "--normals", b.normals, "-o", (d / "out" / "a.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "do not divide into 3 page(s)")) << r.output;
  r = ahd_test::run_cli({"convert", atlas, "--layout", "godot4-packed", "--pages", "4", "--normals", b.normals, "-o",
                         (d / "out" / "a.ktx2").string(), "--direction", "keep", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_manifest(d / "out" / "a.json").layers, 4u);
  // An import file that contradicts --pages, and one that is not a multiple of 4.
  write_import(atlas, 16);
  r = ahd_test::run_cli({"convert", atlas, "--layout", "godot4-packed", "--pages", "2", "--normals", b.normals, "-o", (d / "o2" / "a.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "records 4 page(s)")) << r.output;
  write_import(atlas, 6);
  expect_error([&] { layout_pages(load_layout("godot4-packed"), atlas, 0); }, "not a multiple of the 4 layers per page");
}

TEST(Atlas, AutoDetectionOfEachBakersSet) {
  const WorldBake b("atlas_detect");
  const fs::path& d = b.dir;
  write_bakery_sh(b.w, (d / "Scene_LM0").string());
  LayoutDetection det = detect_layout((d / "Scene_LM0_L1y.tga").string());
  EXPECT_EQ(det.preset, "bakery-sh");
  EXPECT_EQ(det.base, (d / "Scene_LM0").string());
  write_bakery_monosh(b.w, (d / "Scene_LMA1").string());
  EXPECT_EQ(detect_layout((d / "Scene_LMA1_L0.hdr").string()).preset, "bakery-monosh");
  write_unity_directional(b.w, (d / "Lightmap-0").string());
  write_image((d / "Lightmap-0_comp_shadowmask.png").string(), ImageF(N, N, 3));
  det = detect_layout((d / "Lightmap-0_comp_light.exr").string());
  EXPECT_EQ(det.preset, "unity-directional");
  ASSERT_EQ(det.notes.size(), 1u);
  EXPECT_TRUE(contains(det.notes[0], "shadowmask")) << det.notes[0];
  write_image((d / "Lightmap-1_comp_light.exr").string(), coefficient_image(b.w.tangent, 0), true);
  det = detect_layout((d / "Lightmap-1_comp_light.exr").string());
  EXPECT_EQ(det.preset, "plain");
  EXPECT_EQ(det.base, (d / "Lightmap-1_comp_light").string());
  write_exr_layers((d / "layers.exr").string(), b.w.tangent);
  EXPECT_EQ(detect_layout((d / "layers.exr").string()).preset, "exr-layers-l1");
  write_exr_parts((d / "parts.exr").string(), b.w.tangent);
  EXPECT_EQ(detect_layout((d / "parts.exr").string()).preset, "exr-parts-l1");
  write_three_rgba(b.w, (d / "rgba").string());
  EXPECT_EQ(detect_layout((d / "rgba_g.exr").string()).preset, "three-rgba");
  // Godot packed by version and contents; raw by negative L1; a contradiction is ambiguous.
  const fs::path g = d / "godot";
  fs::create_directories(g);
  write_godot_packed(b.w, (g / "lm.exr").string());
  write_import((g / "lm.exr").string(), 4);
  expect_error([&] { detect_layout((g / "lm.exr").string()); }, "candidates: godot4-packed, godot4-unpacked");
  write_project(g, "4.5");
  det = detect_layout((g / "lm.exr").string());
  EXPECT_EQ(det.preset, "godot4-packed");
  write_image((g / "lm_shadow.png").string(), ImageF(N, N, 3));
  EXPECT_EQ(detect_layout((g / "lm.exr").string()).notes.size(), 1u);
  // A lone RGB EXR is a plain lightmap (issue 42), saying why; two channels, or Godot's stacked
  // shape without its import file (rows 4 × columns), are not guessed.
  write_image((d / "lone.exr").string(), ImageF(N, N, 3), true);
  det = detect_layout((d / "lone.exr").string());
  EXPECT_EQ(det.preset, "plain");
  EXPECT_EQ(det.base, (d / "lone").string());
  ASSERT_FALSE(det.reasons.empty());
  EXPECT_NE(det.reasons[0].find("channels R, G, B only"), std::string::npos) << det.reasons[0];
  write_image((d / "two.exr").string(), ImageF(N, N, 2), true);
  expect_error([&] { detect_layout((d / "two.exr").string()); }, "--layout plain");
  EXPECT_FALSE(try_detect_layout((d / "two.exr").string()).has_value());
  write_image((d / "stack.exr").string(), ImageF(N, 4 * N, 3), true);
  EXPECT_FALSE(try_detect_layout((d / "stack.exr").string()).has_value());
  // Both Bakery L1 kinds beside one L0: ambiguous, candidates listed.
  write_image((d / "Scene_LM0_L1.tga").string(), ImageF(N, N, 3));
  expect_error([&] { detect_layout((d / "Scene_LM0_L0.hdr").string()); }, "candidates: bakery-sh, bakery-monosh");
}

TEST(Atlas, GodotRecordsAreRead) {
  AHD_REQUIRE_DATA(kVermilion / "world.exr");
  const GodotImport gi = read_godot_import((kVermilion / "world.exr").string());
  EXPECT_TRUE(gi.found);
  EXPECT_EQ(gi.importer, "2d_array_texture");
  EXPECT_EQ(gi.slices_vertical, 4);
  EXPECT_EQ(godot_project_version((kVermilion / "world.exr").string()), "4.2");
  EXPECT_EQ(godot_version_packs_l1("4.2"), 0);
  EXPECT_EQ(godot_version_packs_l1("4.4.1"), 1);
  EXPECT_EQ(godot_version_packs_l1("3.5"), -1);
  const auto names = godot_resource_names((kVermilion / "world.lmbake").string());
  EXPECT_NE(std::find(names.begin(), names.end(), "uses_spherical_harmonics"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "_uses_packed_directional"), names.end());
}

// Array textures in both containers: KTX2 keeps each level's layers together (layerCount), DDS each
// layer's mip chain together (DX10 arraySize, also for formats that otherwise get a legacy header).
TEST(Atlas, ArrayTexturesRoundTripInBothContainersWithTheSpecsLayout) {
  std::mt19937 rng(3);
  for (PixelFormat f : {PixelFormat::BC4_UNORM, PixelFormat::RGBA8_UNORM, PixelFormat::RGBA16_SFLOAT}) {
    std::vector<Texture> pages(3);
    for (Texture& t : pages) {
      t.format = f;
      for (uint32_t l = 0; l < 3; ++l) {
        TextureLevel lv{std::max(1u, 12u >> l), std::max(1u, 8u >> l), {}};
        lv.data.resize(level_size_bytes(f, lv.width, lv.height));
        for (auto& b : lv.data) b = uint8_t(rng());
        t.levels.push_back(lv);
      }
    }
    const Texture array = stack_layers(pages);
    for (ContainerKind kind : {ContainerKind::KTX2, ContainerKind::DDS}) {
      const std::vector<uint8_t> bytes = encode_container(kind, array);
      const Texture back = decode_container(kind, bytes.data(), bytes.size(), "mem");
      ASSERT_EQ(back.layers, 3u);
      for (uint32_t p = 0; p < 3; ++p)
        for (size_t l = 0; l < 3; ++l) EXPECT_EQ(texture_layer(back, p).levels[l].data, pages[p].levels[l].data);
      if (kind == ContainerKind::DDS) {
        uint32_t fourcc, array_size;
        std::memcpy(&fourcc, &bytes[84], 4);
        std::memcpy(&array_size, &bytes[140], 4);
        EXPECT_EQ(fourcc, 0x30315844u);  // "DX10"
        EXPECT_EQ(array_size, 3u);
        // Layer 1's level 0 follows layer 0's whole chain.
        size_t chain = 0;
        for (const auto& lv : pages[0].levels) chain += lv.data.size();
        EXPECT_TRUE(std::equal(pages[1].levels[0].data.begin(), pages[1].levels[0].data.end(), bytes.begin() + 148 + chain));
      } else {
        uint32_t layer_count;
        std::memcpy(&layer_count, &bytes[32], 4);
        EXPECT_EQ(layer_count, 3u);
      }
      // Truncated arrays are refused like any other file.
      expect_error([&] { decode_container(kind, bytes.data(), bytes.size() - 1, "mem"); }, "mem");
    }
    expect_error([&] { texture_layer(array, 3); }, "layer 3 does not exist");
  }
}

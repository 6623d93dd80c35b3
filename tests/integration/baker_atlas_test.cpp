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
#include "baker_atlas_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

using namespace ahd_fixture::baker_atlas_fixture;

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

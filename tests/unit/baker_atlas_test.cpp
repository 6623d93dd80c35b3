// Atlases in process: every baker's set detected, Godot's records read, array textures in both
// containers. Through the command and on the real bake: tests/integration/baker_atlas_test.cpp.
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

// SceneGltf.*: the placed scene of a conversion's input, for engines (issue 41). The manifest of
// the real Godot 4.2 bake (tests/data/bakes/godot42-vermilion) lists every placed lightmap user
// with the .lmbake's page and rectangle; `ahdpack scene` writes the same instances as glTF with
// TEXCOORD_1 = TEXCOORD_0 · uv_scale + uv_offset, deterministic bytes; inputs without a placed
// scene get no "instances" key (their manifests keep their bytes) and `scene` refuses them.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "bakers/godot/godot_lmbake.h"
#include "cli_runner.h"
#include "files/manifest_file.h"
#include "test_data.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

const fs::path kScenes = ahd_test::test_data("bakes/godot42-vermilion") / "project" / "scenes";

std::vector<uint8_t> bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// Accessor `i` of a .glb as floats (FLOAT components only).
std::vector<float> accessor(const nlohmann::json& g, const std::vector<uint8_t>& b, size_t bin, int i) {
  const auto& a = g["accessors"][size_t(i)];
  const auto& v = g["bufferViews"][a["bufferView"].get<size_t>()];
  EXPECT_EQ(a["componentType"], 5126);
  const size_t n = a["count"].get<size_t>() * (a["type"] == "VEC3" ? 3 : a["type"] == "VEC2" ? 2 : 1);
  std::vector<float> out(n);
  EXPECT_EQ(v["byteLength"].get<size_t>(), n * 4);
  std::memcpy(out.data(), b.data() + bin + v["byteOffset"].get<size_t>(), n * 4);
  return out;
}

}  // namespace

TEST(SceneGltf, GodotSceneInstancesInTheManifestAndTheGltf) {
  if (!fs::exists(kScenes / "world.tscn")) GTEST_SKIP() << "no " << kScenes / "world.tscn";
  const fs::path dir = ahd_test::temp_dir("scene_gltf");
  const std::string exr = (kScenes / "world.exr").string();
  auto r = run_cli({"convert", exr, "-o", (dir / "w.ktx2").string(), "--levels", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_cli({"scene", exr, "-o", (dir / "a.glb").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_cli({"scene", exr, "-o", (dir / "b.glb").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<uint8_t> b = bytes_of(dir / "a.glb");
  EXPECT_EQ(b, bytes_of(dir / "b.glb")) << "same input, same bytes";

  // The manifest: every user the .lmbake names and the reader placed, with its page and rectangle
  // exactly as Godot stores it (uv_scale = size, uv_offset = position, v down).
  const ahd::Manifest m = ahd::read_manifest_file((dir / "w.json").string());
  const ahd::GodotLightmapData lm = ahd::read_godot_lmbake((kScenes / "world.lmbake").string());
  ASSERT_FALSE(m.instances.empty());
  EXPECT_LE(m.instances.size(), lm.users.size());
  size_t matched = 0;
  for (const auto& in : m.instances)
    for (const auto& u : lm.users)
      if (u.path == in.node && u.sub_instance < 0) {
        ++matched;
        EXPECT_EQ(in.page, u.slice) << in.node;
        EXPECT_NEAR(in.scale[0], u.rect[2], 1e-12) << in.node;
        EXPECT_NEAR(in.scale[1], u.rect[3], 1e-12) << in.node;
        EXPECT_NEAR(in.offset[0], u.rect[0], 1e-12) << in.node;
        EXPECT_NEAR(in.offset[1], u.rect[1], 1e-12) << in.node;
        break;
      }
  EXPECT_EQ(matched, m.instances.size());

  // The glTF: a valid GLB (header, JSON chunk, BIN chunk, lengths), one node per instance in the
  // manifest's order, TEXCOORD_1 = TEXCOORD_0 · scale + offset, unit normals.
  ASSERT_GE(b.size(), 28u);
  ASSERT_EQ(std::memcmp(b.data(), "glTF", 4), 0);
  EXPECT_EQ(u32(b, 4), 2u);
  EXPECT_EQ(u32(b, 8), b.size());
  const uint32_t jl = u32(b, 12);
  ASSERT_EQ(u32(b, 16), 0x4E4F534Au);
  const nlohmann::json g = nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + jl);
  const size_t bin = 20 + jl + 8;
  ASSERT_EQ(u32(b, 20 + jl + 4), 0x004E4942u);
  EXPECT_EQ(u32(b, 20 + jl), g["buffers"][0]["byteLength"].get<uint32_t>());
  ASSERT_EQ(g["nodes"].size(), m.instances.size());
  for (size_t i = 0; i < m.instances.size(); ++i) {
    const auto& n = g["nodes"][i];
    EXPECT_EQ(n["name"], m.instances[i].node);
    EXPECT_EQ(n["extras"]["ahd_page"], m.instances[i].page);
    const auto& attrs = g["meshes"][n["mesh"].get<size_t>()]["primitives"][0]["attributes"];
    const std::vector<float> uv0 = accessor(g, b, bin, attrs["TEXCOORD_0"]), uv1 = accessor(g, b, bin, attrs["TEXCOORD_1"]);
    const std::vector<float> nor = accessor(g, b, bin, attrs["NORMAL"]), pos = accessor(g, b, bin, attrs["POSITION"]);
    ASSERT_EQ(uv0.size(), uv1.size());
    ASSERT_EQ(pos.size(), nor.size());
    ASSERT_EQ(uv0.size() / 2, pos.size() / 3);
    for (size_t v = 0; v < uv0.size(); v += 2)
      for (int k = 0; k < 2; ++k)
        ASSERT_NEAR(uv1[v + size_t(k)], uv0[v + size_t(k)] * m.instances[i].scale[k] + m.instances[i].offset[k], 2e-6)
            << m.instances[i].node;
    for (size_t v = 0; v < nor.size(); v += 3)
      ASSERT_NEAR(std::sqrt(nor[v] * nor[v] + nor[v + 1] * nor[v + 1] + nor[v + 2] * nor[v + 2]), 1.0, 1e-4);
  }
}

TEST(SceneGltf, NoPlacedSceneNoInstancesAndSceneRefuses) {
  const fs::path dir = ahd_test::temp_dir("scene_gltf_none");
  ASSERT_EQ(run_cli({"sample", "-o", (dir / "s.exr").string(), "--size", "16"}).exit_code, 0);
  ASSERT_EQ(run_cli({"convert", (dir / "s.exr").string(), "-o", (dir / "s.ktx2").string()}).exit_code, 0);
  std::ifstream f(dir / "s.json");
  const nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_FALSE(j.contains("instances"));
  EXPECT_FALSE(j.contains("instance_uv"));
  const auto r = run_cli({"scene", (dir / "s.exr").string(), "-o", (dir / "s.glb").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("ahdpack: error: " + (dir / "s.exr").string() + ": no placed scene"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "s.glb"));
}

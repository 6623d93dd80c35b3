// Atlas placement for normals (issue 16): three instances of one mesh placed in one atlas by
// scale/offset (ahdpack's JSON, a Unity-style scene YAML) rasterise to the same normals and
// coverage as the same scene whose lightmap UVs were baked into atlas space; overlaps reported.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "fixture_writers.h"
#include "files/file_io.h"
#include "scene/mesh_io.h"
#include "scene/placement_io.h"
#include "layout_test_scene.h"
#include "scene/placement.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

constexpr int kAtlas = 32;

// A tilted quad, normal (0, 0.6, 0.8), lightmap UVs (glTF, v down) inside [1/16, 15/16].
struct Quad {
  std::vector<float> pos = {0, 0, 0, 1, 0, 0, 1, 0.8f, -0.6f, 0, 0.8f, -0.6f};
  std::vector<float> nrm = {0, 0.6f, 0.8f, 0, 0.6f, 0.8f, 0, 0.6f, 0.8f, 0, 0.6f, 0.8f};
  std::vector<float> uv = {1 / 16.f, 15 / 16.f, 15 / 16.f, 15 / 16.f, 15 / 16.f, 1 / 16.f, 1 / 16.f, 1 / 16.f};
  std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
};

struct Node {
  std::string name;
  int mesh;
  std::array<double, 4> rotation;  // x y z w
  std::array<double, 3> translation;
};

// A .gltf: one mesh per entry of `uvs` (the quad with those lightmap UVs), the nodes given.
void write_scene(const std::string& path, const std::vector<std::vector<float>>& uvs, const std::vector<Node>& nodes) {
  const Quad q;
  std::vector<uint8_t> buf;
  std::vector<std::pair<size_t, size_t>> views;
  auto add = [&](const void* p, size_t bytes) {
    while (buf.size() % 4) buf.push_back(0);
    views.push_back({buf.size(), bytes});
    buf.insert(buf.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + bytes);
  };
  add(q.pos.data(), 48);
  add(q.nrm.data(), 48);
  add(q.idx.data(), 24);
  for (const auto& uv : uvs) add(uv.data(), 32);
  std::ostringstream j;
  j.precision(17);
  j << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[)";
  for (size_t i = 0; i < nodes.size(); ++i) j << (i ? "," : "") << i;
  j << "]}],\"nodes\":[";
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    j << (i ? "," : "") << R"({"name":")" << n.name << R"(","mesh":)" << n.mesh << R"(,"rotation":[)" << n.rotation[0] << ","
      << n.rotation[1] << "," << n.rotation[2] << "," << n.rotation[3] << R"(],"translation":[)" << n.translation[0] << ","
      << n.translation[1] << "," << n.translation[2] << "]}";
  }
  j << "],\"meshes\":[";
  for (size_t m = 0; m < uvs.size(); ++m)
    j << (m ? "," : "") << R"({"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":)" << 3 + m << R"(},"indices":2}]})";
  j << R"(],"buffers":[{"byteLength":)" << buf.size() << R"(,"uri":"data:application/octet-stream;base64,)" << ahd_test::base64(buf)
    << R"("}],"bufferViews":[)";
  for (size_t i = 0; i < views.size(); ++i)
    j << (i ? "," : "") << R"({"buffer":0,"byteOffset":)" << views[i].first << R"(,"byteLength":)" << views[i].second << "}";
  j << R"(],"accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,-0.6],"max":[1,0.8,0]},)"
    << R"({"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},)"
    << R"({"bufferView":2,"componentType":5125,"count":6,"type":"SCALAR"})";
  for (size_t m = 0; m < uvs.size(); ++m) j << R"(,{"bufferView":)" << 3 + m << R"(,"componentType":5126,"count":4,"type":"VEC2"})";
  j << "]}";
  std::ofstream(path) << j.str();
}

// The three instances: names, rotations (identity, 180° about x, 180° about y: normals
// (0, .6, .8), (0, −.6, −.8), (0, .6, −.8)) and their atlas rectangles (scale, offset; v up).
const std::vector<Node> kNodes = {{"Chair", 0, {0, 0, 0, 1}, {0, 0, 0}},
                                  {"Table", 0, {1, 0, 0, 0}, {3, 0, 0}},
                                  {"Lamp", 0, {0, 1, 0, 0}, {0, 0, 3}}};
const double kPlace[3][4] = {{0.5, 0.5, 0, 0.5}, {0.5, 0.5, 0.5, 0.5}, {0.5, 0.25, 0.25, 0}};

// The same UVs moved into atlas space by hand (glTF's v down: v' = 1 − ((1 − v)·sy + oy)).
std::vector<float> baked_uv(int k) {
  std::vector<float> uv = Quad().uv;
  for (size_t v = 0; v < 4; ++v) {
    uv[v * 2] = float(uv[v * 2] * kPlace[k][0] + kPlace[k][2]);
    uv[v * 2 + 1] = float(1 - ((1 - uv[v * 2 + 1]) * kPlace[k][1] + kPlace[k][3]));
  }
  return uv;
}

void write_json(const std::string& path, const double place[3][4]) {
  std::ofstream f(path);
  f << "{\"placements\": [";
  for (int k = 0; k < 3; ++k)
    f << (k ? "," : "") << "{\"node\": \"" << kNodes[size_t(k)].name << "\", \"page\": 0, \"scale\": [" << place[k][0] << ", "
      << place[k][1] << "], \"offset\": [" << place[k][2] << ", " << place[k][3] << "]}";
  f << "]}\n";
}

void write_unity(const std::string& path) {
  std::ofstream f(path);
  f << "%YAML 1.1\n%TAG !u! tag:unity3d.com,2011:\n";
  for (int k = 0; k < 3; ++k) {
    f << "--- !u!1 &" << 100 + k << "\nGameObject:\n  m_ObjectHideFlags: 0\n  m_Component:\n  - component: {fileID: " << 200 + k
      << "}\n  m_Layer: 0\n  m_Name: " << kNodes[size_t(k)].name << "\n";
    f << "--- !u!23 &" << 200 + k << "\nMeshRenderer:\n  m_GameObject: {fileID: " << 100 + k
      << "}\n  m_Enabled: 1\n  m_LightmapIndex: 0\n  m_LightmapTilingOffset: {x: " << kPlace[k][0] << ", y: " << kPlace[k][1]
      << ", z: " << kPlace[k][2] << ", w: " << kPlace[k][3] << "}\n  m_LightmapIndexDynamic: 65535\n";
  }
  // A renderer that is not lightmapped, and a GameObject without a renderer.
  f << "--- !u!1 &300\nGameObject:\n  m_Name: Sky\n--- !u!23 &301\nMeshRenderer:\n  m_GameObject: {fileID: 300}\n"
       "  m_LightmapIndex: 65535\n  m_LightmapTilingOffset: {x: 1, y: 1, z: 0, w: 0}\n--- !u!1 &302\nGameObject:\n  m_Name: Empty\n";
}

void expect_same_raster(const RasterisedNormals& a, const RasterisedNormals& b, const std::string& what) {
  EXPECT_EQ(a.coverage, b.coverage) << what;
  double worst = 0;
  for (size_t i = 0; i < a.normals.size(); ++i) worst = std::max(worst, double(std::fabs(a.normals[i] - b.normals[i])));
  EXPECT_LT(worst, 1e-6) << what;
}

}  // namespace

TEST(Placement, InstancesPlacedByJsonAndUnityYamlEqualUvsBakedIntoTheAtlas) {
  const fs::path d = ahd_test::temp_dir("placement");
  write_scene((d / "instanced.gltf").string(), {Quad().uv}, kNodes);
  std::vector<Node> baked_nodes = kNodes;
  for (int k = 0; k < 3; ++k) baked_nodes[size_t(k)].mesh = k;
  write_scene((d / "baked.gltf").string(), {baked_uv(0), baked_uv(1), baked_uv(2)}, baked_nodes);
  write_json((d / "p.json").string(), kPlace);
  write_unity((d / "scene.unity").string());

  const RasterisedNormals want = rasterise_lightmap_normals(read_mesh_lightmap((d / "baked.gltf").string(), -1), kAtlas, kAtlas);
  size_t covered = 0;
  for (uint8_t c : want.coverage) covered += c;
  EXPECT_GT(covered, 300u);
  // The three normals are where the rectangles put them (row 0 = top = v 1: Chair top left).
  const float* chair = &want.normals[(4 * kAtlas + 4) * 3];
  const float* table = &want.normals[(4 * kAtlas + 20) * 3];
  const float* lamp = &want.normals[(28 * kAtlas + 12) * 3];
  EXPECT_NEAR(chair[1], 0.6, 1e-6);
  EXPECT_NEAR(chair[2], 0.8, 1e-6);
  EXPECT_NEAR(table[1], -0.6, 1e-6);
  EXPECT_NEAR(table[2], -0.8, 1e-6);
  EXPECT_NEAR(lamp[1], 0.6, 1e-6);
  EXPECT_NEAR(lamp[2], -0.8, 1e-6);

  const MeshInstances scene = read_mesh_instances((d / "instanced.gltf").string(), -1);
  ASSERT_EQ(scene.instances.size(), 3u);
  for (const char* file : {"p.json", "scene.unity"}) {
    const std::vector<Placement> pl = read_placements((d / file).string());
    ASSERT_EQ(pl.size(), 3u) << file;
    const PlacedMesh pm = place_instances(scene, pl, 0, file);
    EXPECT_EQ(pm.placed.size(), 3u);
    EXPECT_TRUE(pm.overlaps.empty()) << file;
    expect_same_raster(rasterise_lightmap_normals(pm.mesh, kAtlas, kAtlas), want, file);
    EXPECT_TRUE(place_instances(scene, pl, 1, file).mesh.indices.empty());  // nothing on page 1
  }
  // Without placement the three instances pile up in the same rectangle: a different raster.
  const RasterisedNormals piled = rasterise_lightmap_normals(scene.mesh, kAtlas, kAtlas);
  EXPECT_NE(piled.coverage, want.coverage);

  // Overlapping rectangles are reported; unknown nodes and bad scales refused.
  const double overlapping[3][4] = {{0.5, 0.5, 0, 0.5}, {0.5, 0.5, 0.25, 0.5}, {0.5, 0.25, 0.25, 0}};
  write_json((d / "over.json").string(), overlapping);
  const PlacedMesh over = place_instances(scene, read_placements((d / "over.json").string()), 0, "over.json");
  ASSERT_EQ(over.overlaps.size(), 1u);
  EXPECT_EQ(over.overlaps[0], "'Chair' and 'Table'");
  std::vector<Placement> bad = read_placements((d / "p.json").string());
  bad[0].node = "Sofa";
  expect_error([&] { place_instances(scene, bad, 0, "p.json"); }, "'Sofa', which is no mesh instance");
  bad = read_placements((d / "p.json").string());
  bad[1].scale[0] = 0;
  expect_error([&] { place_instances(scene, bad, 0, "p.json"); }, "finite positive scale");
  std::ofstream(d / "broken.json") << "{\"placements\": [{\"node\": 3}]}";
  expect_error([&] { read_placements((d / "broken.json").string()); }, "malformed placement JSON");
  fs::remove_all(d);
}

TEST(Placement, ConvertWithPlacementFromTheCommandLine) {
  const WorldBake b("placement_cli");
  const fs::path& d = b.dir;
  write_scene((d / "instanced.gltf").string(), {Quad().uv}, kNodes);
  std::vector<Node> baked_nodes = kNodes;
  for (int k = 0; k < 3; ++k) baked_nodes[size_t(k)].mesh = k;
  write_scene((d / "baked.gltf").string(), {baked_uv(0), baked_uv(1), baked_uv(2)}, baked_nodes);
  write_json((d / "p.json").string(), kPlace);
  write_unity((d / "scene.unity").string());
  // A Godot-packed 32×32 page: uniform L0, L1 along +y.
  ImageF img(kAtlas, 4 * kAtlas, 3);
  for (int y = 0; y < kAtlas; ++y)
    for (int x = 0; x < kAtlas; ++x)
      for (int c = 0; c < 3; ++c) {
        img.at(x, y)[c] = 1;
        img.at(x, y + kAtlas)[c] = 0.55f, img.at(x, y + 2 * kAtlas)[c] = 0.5f, img.at(x, y + 3 * kAtlas)[c] = 0.5f;
      }
  write_image((d / "lm.exr").string(), img, true);
  auto convert = [&](const std::string& mesh, const std::string& placement, const std::string& out) {
    std::vector<std::string> args = {"convert", (d / "lm.exr").string(), "--layout", "godot4-packed", "--mesh", (d / mesh).string(),
                                     "-o", (d / out).string(), "--direction", "keep", "--levels", "1"};
    if (!placement.empty()) args.insert(args.end(), {"--placement", (d / placement).string()});
    return ahd_test::run_cli(args);
  };
  auto r = convert("baked.gltf", "", "baked/a.ktx2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* p : {"p.json", "scene.unity"}) {
    r = convert("instanced.gltf", p, std::string("placed_") + p + "/a.ktx2");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("3 instance(s) placed by"), std::string::npos) << r.output;
    // The direction plane depends on the normals: equal to the baked scene's, byte for byte.
    const auto bytes = [](const fs::path& f) { return read_file_bytes(f.string()); };
    const auto plane = [&](const std::string& dir, const char* name) {
      return ahd_test::plane_file((d / dir / "a.json").string(), name);
    };
    for (const char* name : {"dir", "iz"}) {
      ASSERT_FALSE(plane(std::string("placed_") + p, name).empty()) << p;
      EXPECT_EQ(bytes(plane(std::string("placed_") + p, name)), bytes(plane("baked", name))) << p << " " << name;
    }
  }
  // Issue 25: the three instances share their UVs; without placement they would be merged on top of
  // each other: refused naming the file and the remedy, converted with --allow-mismatch.
  r = convert("instanced.gltf", "", "unplaced/a.ktx2");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("ahdpack: error: " + (d / "instanced.gltf").string() + ": 3 pair(s) of instances overlap in UV set 0"),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--placement"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "unplaced"));
  {
    std::vector<std::string> args = {"convert", (d / "lm.exr").string(), "--layout", "godot4-packed", "--mesh",
                                     (d / "instanced.gltf").string(), "--allow-mismatch", "-o", (d / "unplaced" / "a.ktx2").string(),
                                     "--levels", "1"};
    EXPECT_EQ(ahd_test::run_cli(args).exit_code, 0);
  }
  const double overlapping[3][4] = {{0.5, 0.5, 0, 0.5}, {0.5, 0.5, 0.25, 0.5}, {0.5, 0.25, 0.25, 0}};
  write_json((d / "over.json").string(), overlapping);
  r = convert("instanced.gltf", "over.json", "over/a.ktx2");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("instances 'Chair' and 'Table' overlap"), std::string::npos) << r.output;
  r = ahd_test::run_cli({"convert", (d / "lm.exr").string(), "--layout", "godot4-packed", "--normals", b.normals, "--placement",
                         (d / "p.json").string(), "-o", (d / "x" / "a.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--placement needs --mesh"), std::string::npos) << r.output;
}

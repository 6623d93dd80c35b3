// What the placement tests share (tests/unit and tests/integration baker_placement_test.cpp).
#pragma once
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

namespace ahd_fixture::baker_placement_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;
using namespace layout_test;

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
inline void write_scene(const std::string& path, const std::vector<std::vector<float>>& uvs, const std::vector<Node>& nodes) {
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
inline std::vector<float> baked_uv(int k) {
  std::vector<float> uv = Quad().uv;
  for (size_t v = 0; v < 4; ++v) {
    uv[v * 2] = float(uv[v * 2] * kPlace[k][0] + kPlace[k][2]);
    uv[v * 2 + 1] = float(1 - ((1 - uv[v * 2 + 1]) * kPlace[k][1] + kPlace[k][3]));
  }
  return uv;
}

inline void write_json(const std::string& path, const double place[3][4]) {
  std::ofstream f(path);
  f << "{\"placements\": [";
  for (int k = 0; k < 3; ++k)
    f << (k ? "," : "") << "{\"node\": \"" << kNodes[size_t(k)].name << "\", \"page\": 0, \"scale\": [" << place[k][0] << ", "
      << place[k][1] << "], \"offset\": [" << place[k][2] << ", " << place[k][3] << "]}";
  f << "]}\n";
}

inline void write_unity(const std::string& path) {
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

inline void expect_same_raster(const RasterisedNormals& a, const RasterisedNormals& b, const std::string& what) {
  EXPECT_EQ(a.coverage, b.coverage) << what;
  double worst = 0;
  for (size_t i = 0; i < a.normals.size(); ++i) worst = std::max(worst, double(std::fabs(a.normals[i] - b.normals[i])));
  EXPECT_LT(worst, 1e-6) << what;
}

// The placement tests' inputs in `d`: instanced.gltf (one quad, three nodes), baked.gltf (each
// node's UVs already in the atlas), p.json and scene.unity placing the instanced nodes.
inline void write_placement_inputs(const fs::path& d) {
  write_scene((d / "instanced.gltf").string(), {Quad().uv}, kNodes);
  std::vector<Node> baked_nodes = kNodes;
  for (int k = 0; k < 3; ++k) baked_nodes[size_t(k)].mesh = k;
  write_scene((d / "baked.gltf").string(), {baked_uv(0), baked_uv(1), baked_uv(2)}, baked_nodes);
  write_json((d / "p.json").string(), kPlace);
  write_unity((d / "scene.unity").string());
}

}  // namespace ahd_fixture::baker_placement_fixture

// Meshes through the command: bad meshes, --mesh against --normals, mesh axes. In-process tests:
// tests/unit/mesh_raster_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cli_runner.h"
#include "files/container_file.h"
#include "core/error.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "scene/mesh_io.h"
#include "layout_test_scene.h"
#include "scene/lightmap_raster.h"
#include "sample/analytic_baker.h"
#include "sh/sh.h"
#include "mesh_raster_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::mesh_raster_fixture;


TEST(MeshRaster, BadMeshesGiveOneClearError) {
  const fs::path d = ahd_test::temp_dir("mesh_bad");
  const TestMesh cyl = cylinder();
  write_obj((d / "c.obj").string(), cyl);
  write_obj((d / "nouv.obj").string(), cyl, true, false);
  std::ofstream(d / "lines.obj") << "v 0 0 0\nv 1 0 0\nvt 0 0\nl 1 2\n";
  std::ofstream(d / "c.fbx") << "x";
  std::ofstream(d / "junk.gltf") << "{ not json";
  using layout_test::expect_error;  // one ahd::Error, one line, naming the cause
  expect_error([&] { read_mesh_lightmap((d / "none.obj").string(), -1); }, "none.obj: file not found");
  expect_error([&] { read_mesh_lightmap((d / "c.obj").string(), 1); }, "UV set 1 requested, mesh");
  expect_error([&] { read_mesh_lightmap((d / "c.obj").string(), 1); }, "has 1 UV set (0..0)");
  expect_error([&] { read_mesh_lightmap((d / "nouv.obj").string(), -1); }, "has no UVs");
  expect_error([&] { read_mesh_lightmap((d / "lines.obj").string(), -1); }, "lines.obj: no triangles");
  expect_error([&] { read_mesh_lightmap((d / "c.fbx").string(), -1); }, "unsupported mesh format '.fbx'");
  expect_error([&] { read_mesh_lightmap((d / "junk.gltf").string(), -1); }, "junk.gltf: cannot read mesh");

  // The command line: one line, non-zero exit, nothing written.
  BakerOptions bo;
  bo.width = bo.height = 8;
  bo.coeffs = 4;
  const ShImage sh = bake_analytic_scene(bo);
  ImageF packed(8, 32, 3), normals(8, 8, 3);
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      packed.data[i * 3 + size_t(c)] = sh.texel(i)[c];
      for (int k = 1; k < 4; ++k) packed.data[(i + size_t(k) * 64) * 3 + size_t(c)] = 0.5f;
      normals.data[i * 3 + 2] = 1;
    }
  write_image((d / "lm.exr").string(), packed, true);
  write_image((d / "n.exr").string(), normals);
  const std::string out = (d / "out" / "a.ktx2").string();
  auto fails = [&](std::vector<std::string> extra, const std::string& needle) {
    std::vector<std::string> args = {"convert", (d / "lm").string(), "--layout", "godot4-packed", "-o", out};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = ahd_test::run_cli(args);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.output;
    EXPECT_FALSE(fs::exists(d / "out")) << "output written";
  };
  fails({"--mesh", (d / "none.obj").string()}, "none.obj: file not found");
  fails({"--mesh", (d / "c.obj").string(), "--uv-set", "1"}, "has 1 UV set");
  fails({"--mesh", (d / "nouv.obj").string()}, "has no UVs");
  fails({"--mesh", (d / "c.obj").string(), "--normals", (d / "n.exr").string()}, "--mesh and --normals");
  fails({"--uv-set", "1", "--normals", (d / "n.exr").string()}, "--uv-set needs --mesh");
  // A chart outside the image (UVs of the decoy range shifted away): refused, not a black map.
  TestMesh away = cyl;
  for (float& v : away.lm_uv) v += 3;
  write_obj((d / "away.obj").string(), away);
  fails({"--mesh", (d / "away.obj").string()}, "no triangle covers any texel");
  // Sanity: the same command with a good mesh succeeds (so the failures above are the inputs').
  const auto ok = ahd_test::run_cli({"convert", (d / "lm").string(), "--layout", "godot4-packed", "--mesh",
                                     (d / "c.obj").string(), "-o", out, "-q"});
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  fs::remove_all(d);
}

namespace {

// The layout tests' scene: floor chart on the left half (n = +y), wall on the right (n = +z),
// 16×16 with a 1-texel gutter around each chart.
constexpr int kN = layout_test::N;

// The layout tests' scene (layout_test_scene.h), stored Godot-packed, and its normal map.
void write_godot_packed_scene(const std::string& lm, const std::string& normals_exr) {
  const layout_test::WorldScene w = layout_test::world_scene();
  layout_test::write_godot_packed(w, lm);
  write_image(normals_exr, w.normals);
}

// Two quads whose lightmap charts are the scene's (x ∈ [1, 7] and [9, 15], y ∈ [1, 15] texels)
// with the baker's world placement: floor p = (−1 + 2u, 0, 2v), wall p = (−1 + 2u, 2 − 2v, 0).
TestMesh floor_and_wall() {
  TestMesh m;
  for (int wall = 0; wall < 2; ++wall) {
    const uint32_t base = uint32_t(m.verts());
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        if (wall) m.pos.insert(m.pos.end(), {float(-1 + 2 * i), float(2 - 2 * j), 0.0f});
        else m.pos.insert(m.pos.end(), {float(-1 + 2 * i), 0.0f, float(2 * j)});
        m.nrm.insert(m.nrm.end(), {0.0f, wall ? 0.0f : 1.0f, wall ? 1.0f : 0.0f});
        const float x0 = wall ? 9 : 1;
        m.lm_uv.insert(m.lm_uv.end(), {(x0 + 6 * i) / kN, (1.0f + 14 * j) / kN});
      }
    m.idx.insert(m.idx.end(), {base, base + 2, base + 3, base, base + 3, base + 1});
  }
  return m;
}

std::vector<char> bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(MeshRaster, ConvertWithMeshEqualsConvertWithTheNormalMap) {
  const fs::path d = ahd_test::temp_dir("mesh_e2e");
  write_godot_packed_scene((d / "lm.exr").string(), (d / "n.exr").string());
  const TestMesh fw = floor_and_wall();
  write_obj((d / "m.obj").string(), fw);
  write_gltf((d / "m.gltf").string(), fw);
  // The rasterised normals are the normal map's on the charts, and the coverage is the charts'.
  const RasterisedNormals r = rasterise_lightmap_normals(read_mesh_lightmap((d / "m.obj").string(), -1), kN, kN);
  const ImageF n = read_image((d / "n.exr").string());
  size_t covered = 0;
  for (int y = 0; y < kN; ++y)
    for (int x = 0; x < kN; ++x) {
      const size_t i = size_t(y) * kN + x;
      const bool chart = y >= 1 && y < kN - 1 && ((x >= 1 && x < 7) || (x >= 9 && x < 15));
      EXPECT_EQ(r.coverage[i], chart ? 1 : 0) << x << "," << y;
      covered += r.coverage[i];
      if (!chart) continue;
      for (int a = 0; a < 3; ++a) EXPECT_EQ(r.normals[i * 3 + size_t(a)], n.at(x, y)[a]) << x << "," << y;
    }
  EXPECT_EQ(covered, 2u * 6 * 14);

  auto convert = [&](const std::string& tag, std::vector<std::string> extra) {
    std::vector<std::string> args = {"convert", (d / "lm").string(), "--layout", "godot4-packed", "-o",
                                     (d / tag / "a.ktx2").string(), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto res = ahd_test::run_cli(args);
    EXPECT_EQ(res.exit_code, 0) << res.output;
  };
  convert("normals", {"--normals", (d / "n.exr").string()});
  convert("obj", {"--mesh", (d / "m.obj").string()});
  convert("gltf", {"--mesh", (d / "m.gltf").string()});
  // Bit-exact: the same normals on every covered texel and the same coverage (the mesh's charts
  // are where the SH is non-zero), so the fit, dilation and encoding see identical inputs.
  for (const char* plane : {"iz", "dir", "ratio"}) {
    auto file = [&](const char* tag) { return fs::path(ahd_test::plane_file((d / tag / "a.json").string(), plane)); };
    const auto ref = bytes(file("normals"));
    ASSERT_GT(ref.size(), 100u) << plane;
    EXPECT_TRUE(bytes(file("obj")) == ref) << plane << " differs (obj)";
    EXPECT_TRUE(bytes(file("gltf")) == ref) << plane << " differs (gltf)";
  }
  // A tangent-space layout takes the mesh's coverage only: a flat map, non-zero everywhere
  // (all texels covered without the mesh), is covered exactly on the mesh's charts.
  ImageF flat(kN, kN, 3);
  std::fill(flat.data.begin(), flat.data.end(), 0.3f);
  write_image((d / "flat.exr").string(), flat);
  for (bool mesh : {false, true}) {
    std::vector<std::string> args = {"convert", (d / "flat").string(), "--layout", "plain", "--coverage-plane", "-o",
                                     (d / "plain" / "p.ktx2").string(), "-q"};
    if (mesh) args.insert(args.end(), {"--mesh", (d / "m.obj").string()});
    const auto res = ahd_test::run_cli(args);
    ASSERT_EQ(res.exit_code, 0) << res.output;
    const Texture cov = read_container_file(ahd_test::plane_file((d / "plain" / "p.json").string(), "coverage"));
    ASSERT_EQ(cov.levels[0].data.size(), size_t(kN * kN));
    for (size_t i = 0; i < r.coverage.size(); ++i)
      EXPECT_EQ(cov.levels[0].data[i], mesh ? r.coverage[i] * 255 : 255) << i;
  }
  fs::remove_all(d);
}

// Unity-world bakers (Bakery) are left-handed; a mesh exported to glTF/OBJ has x negated. The
// preset's mesh_axes brings the mesh's normals into the baker's world: the same planes as the
// baker's own normal map, and different ones without the key.
TEST(MeshRaster, MeshAxesBringGltfNormalsIntoTheBakersWorld) {
  const fs::path d = ahd_test::temp_dir("mesh_axes");
  const layout_test::WorldScene w = layout_test::world_scene();
  layout_test::write_bakery_sh(w, (d / "lm").string());
  // Tilted charts (normals with an x component), in glTF axes on the mesh…
  TestMesh m = floor_and_wall();
  for (size_t v = 0; v < m.verts(); ++v) {
    const bool wall = m.nrm[v * 3 + 2] > 0.5f;
    const float n[3] = {wall ? -0.6f : 0.6f, wall ? 0.0f : 0.8f, wall ? 0.8f : 0.0f};
    std::copy(n, n + 3, &m.nrm[v * 3]);
  }
  write_obj((d / "m.obj").string(), m);
  // …and in Unity's axes (x negated) in the baker's normal map.
  ImageF nmap(kN, kN, 3);
  for (int y = 0; y < kN; ++y)
    for (int x = 0; x < kN; ++x) {
      const bool wall = x >= kN / 2;
      const float n[3] = {wall ? 0.6f : -0.6f, wall ? 0.0f : 0.8f, wall ? 0.8f : 0.0f};
      std::copy(n, n + 3, nmap.at(x, y));
    }
  write_image((d / "n.exr").string(), nmap);
  // The same preset without mesh_axes.
  std::ifstream in(std::string(AHD_SOURCE_DIR) + "/formats/bakers/bakery-sh.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t at = text.find("  \"mesh_axes\"");
  ASSERT_NE(at, std::string::npos);
  text.erase(at, text.find('\n', at) - at + 1);
  std::ofstream((d / "no-axes.json").string()) << text;

  auto convert = [&](const std::string& tag, const std::string& layout, std::vector<std::string> extra) {
    std::vector<std::string> args = {"convert", (d / "lm").string(), "--layout", layout, "--direction", "keep",
                                     "-o", (d / tag / "a.ktx2").string(), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto res = ahd_test::run_cli(args);
    EXPECT_EQ(res.exit_code, 0) << res.output;
  };
  // The normal map covers every texel; the mesh only its charts: give the map the same coverage.
  convert("map", "bakery-sh", {"--normals", (d / "n.exr").string()});
  convert("mesh", "bakery-sh", {"--mesh", (d / "m.obj").string()});
  convert("mesh-no-axes", (d / "no-axes.json").string(), {"--mesh", (d / "m.obj").string()});
  auto dir_plane = [&](const char* tag) { return fs::path(ahd_test::plane_file((d / tag / "a.json").string(), "dir")); };
  const auto ref = bytes(dir_plane("map")), with = bytes(dir_plane("mesh")), without = bytes(dir_plane("mesh-no-axes"));
  ASSERT_GT(ref.size(), 100u);
  EXPECT_TRUE(with == ref) << "mesh normals not brought into the baker's axes";
  EXPECT_FALSE(without == ref) << "mesh_axes has no effect";

  // The key itself: signed axes, each once.
  LayoutPreset bakery = load_layout("bakery-sh");
  std::vector<float> n = {0.6f, 0.0f, 0.8f};
  mesh_normals_to_layout_axes(bakery, &n);
  EXPECT_EQ(n, (std::vector<float>{-0.6f, 0.0f, 0.8f}));
  std::ofstream((d / "bad.json").string())
      << R"({"name":"bad","coeffs":4,"space":"world","mesh_axes":["x","x","z"],"files":[{"pattern":"{base}.exr"}],)"
      << R"("coefficients":[{"file":0}]})";
  layout_test::expect_error([&] { load_layout((d / "bad.json").string()); }, "mesh_axes must name x, y and z once each");
  fs::remove_all(d);
}

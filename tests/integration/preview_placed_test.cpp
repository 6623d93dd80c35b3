// The preview's 3D view of a Godot project: `ahdpack preview W.json --source world.exr` shows the
// project's placed scene (bakers/scene_export.h bake_placed_mesh, the mesh `ahdpack scene` writes),
// each instance at its .lmbake atlas rectangle, not the sample's plane. Checked on the data the
// view is given (view3d_data.js): the triangles' lightmap coordinates, rasterised over the atlas,
// cover exactly the texels the source's coverage says (which the conversion rasterised from the
// same placed scene), on page 0. Also: the Godot reader's and the preview's messages name paths as
// the user gave them (relative stays relative).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "file_bytes.h"
#include "scene/lightmap_raster.h"
#include "scene/mesh_io.h"
#include "test_data.h"

namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> unbase64(const std::string& s) {
  std::vector<uint8_t> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    int v = c >= 'A' && c <= 'Z'   ? c - 'A'
            : c >= 'a' && c <= 'z' ? c - 'a' + 26
            : c >= '0' && c <= '9' ? c - '0' + 52
            : c == '+'             ? 62
            : c == '/'             ? 63
                                   : -1;
    if (v < 0) continue;
    acc = (acc << 6) | uint32_t(v), bits += 6;
    if (bits >= 8) bits -= 8, out.push_back(uint8_t(acc >> bits));
  }
  return out;
}

template <class T>
std::vector<T> as(const std::vector<uint8_t>& b) {
  std::vector<T> v(b.size() / sizeof(T));
  std::memcpy(v.data(), b.data(), v.size() * sizeof(T));
  return v;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(Preview3d, GodotProjectIsPlacedByItsLmbake) {
  const fs::path exr = ahd_test::test_data("bakes/godot42-vermilion/project/scenes/world.exr");
  AHD_REQUIRE_DATA(exr);
  const fs::path dir = ahd_test::temp_dir("preview3d_placed");
  const auto c = ahd_test::run_cli({"convert", exr.string(), "-o", (dir / "c/w.ktx2").string(), "--levels", "1"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const auto p = ahd_test::run_cli(
      {"preview", (dir / "c/w.json").string(), "--source", exr.string(), "-o", (dir / "page").string()});
  ASSERT_EQ(p.exit_code, 0) << p.output;
  if (!fs::exists(dir / "page/view3d_data.js")) GTEST_SKIP() << "no 3D view written (three.js not found?)";
  std::string js = ahd_test::read_text(dir / "page/view3d_data.js");
  const size_t at = js.find('{');
  ASSERT_NE(at, std::string::npos);
  js = js.substr(at, js.rfind('}') - at + 1);
  const nlohmann::json v = nlohmann::json::parse(js);
  EXPECT_TRUE(contains(v.at("mesh_name").get<std::string>(), "placed scene (55 instances)")) << v.at("mesh_name");
  const std::vector<float> st = as<float>(unbase64(v.at("mesh").at("st")));
  const std::vector<uint32_t> idx = as<uint32_t>(unbase64(v.at("mesh").at("indices")));
  const std::vector<int32_t> page = as<int32_t>(unbase64(v.at("mesh").at("page")));
  const std::vector<uint8_t> coverage = unbase64(v.at("coverage"));
  const int w = v.at("width"), h = v.at("height");
  ASSERT_EQ(page.size() * 3, idx.size());
  ASSERT_EQ(coverage.size(), size_t(w) * size_t(h));
  for (int32_t pg : page) EXPECT_EQ(pg, 0);
  // The view's triangles at their (s, t) (t down), rasterised as the conversion rasterises meshes.
  ahd::MeshTriangles m;
  m.positions = as<float>(unbase64(v.at("mesh").at("positions")));
  ASSERT_EQ(m.positions.size() / 3, st.size() / 2);
  m.uv.resize(st.size());
  for (size_t i = 0; i < st.size() / 2; ++i) m.uv[i * 2] = st[i * 2], m.uv[i * 2 + 1] = 1.0f - st[i * 2 + 1];
  m.indices = idx;
  const std::vector<uint8_t> raster = ahd::rasterise_lightmap_normals(m, w, h).coverage;
  size_t both = 0, either = 0, covered = 0;
  for (size_t i = 0; i < coverage.size(); ++i) {
    both += coverage[i] && raster[i], either += coverage[i] || raster[i], covered += coverage[i] != 0;
  }
  std::printf("preview 3D view: %zu triangles, %zu texels covered by the source, IoU with the view's triangles %.4f\n",
              page.size(), covered, either ? double(both) / double(either) : 0.0);
  EXPECT_GT(covered, 100000u);  // vermilion: 147 524 (docs/godot.md)
  EXPECT_GE(double(both), 0.99 * double(either));
  fs::remove_all(dir);
}

// Paths in messages as the user gave them: a Godot project's bad unwrap cache named relative to
// the working folder the command ran in, and preview's missing output folder likewise.
TEST(GodotScene, RelativePathsStayRelativeInMessages) {
  const fs::path project = ahd_test::test_data("godot/corpus/fbx");
  AHD_REQUIRE_DATA(project / "scenes/room.exr");
  const fs::path dir = ahd_test::temp_dir("godot_relative_paths");
  fs::copy(project, dir / "p", fs::copy_options::recursive);
  fs::resize_file(dir / "p/models/room_zup.fbx.unwrap_cache", 30);  // truncated: an entry beyond the file
  fs::create_directories(dir / "run");
  const std::string cli = std::string("'") + AHD_CLI_PATH + "'";
  const std::string o = ahd_test::run_shell("cd '" + (dir / "run").string() + "' && " + cli +
                                            " convert ../p/scenes/room.exr -o out/room.ktx2 2>&1; echo rc=$?");
  EXPECT_TRUE(contains(o, "rc=1")) << o;
  EXPECT_TRUE(contains(o, "ahdpack: error: ../p/models/room_zup.fbx.unwrap_cache: not a readable Godot unwrap cache"))
      << o;
  EXPECT_FALSE(contains(o, dir.string())) << o;
  EXPECT_FALSE(fs::exists(dir / "run/out"));

  // preview -o into a folder that does not exist.
  fs::copy(project, dir / "q", fs::copy_options::recursive);
  const std::string conv = ahd_test::run_shell("cd '" + (dir / "run").string() + "' && " + cli +
                                               " convert ../q/scenes/room.exr -o c/room.ktx2 2>&1; echo rc=$?");
  ASSERT_TRUE(contains(conv, "rc=0")) << conv;
  const std::string pv = ahd_test::run_shell("cd '" + (dir / "run").string() + "' && " + cli +
                                             " preview c/room.json -o nothere/page 2>&1; echo rc=$?");
  EXPECT_TRUE(contains(pv, "rc=1")) << pv;
  EXPECT_TRUE(contains(pv, "ahdpack: error: nothere: no such folder")) << pv;
  EXPECT_FALSE(contains(pv, dir.string())) << pv;
  fs::remove_all(dir);
}

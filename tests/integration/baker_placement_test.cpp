// --mesh with --placement through the command. In-process test: tests/unit/baker_placement_test.cpp.
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
#include "baker_placement_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;
using namespace ahd_fixture::baker_placement_fixture;


TEST(Placement, ConvertWithPlacementFromTheCommandLine) {
  const WorldBake b("placement_cli");
  const fs::path& d = b.dir;
  write_placement_inputs(d);
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

// An FBX project whose cache lost an entry, through the command: refused by default, counted with
// --allow-unplaced. In-process reader tests: tests/unit/godot_reader_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "fixture_writers.h"
#include "bakers/godot/godot_fbx.h"
#include "bakers/godot/godot_unwrap_key.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "core/error.h"
#include "bakers/godot/godot_lmbake.h"
#include "bakers/godot/godot_scene.h"
#include "bakers/godot/godot_tscn.h"
#include "bakers/godot/godot_unwrap_cache.h"
#include "test_data.h"
#include "godot_reader_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::godot_reader_fixture;


// A cache entry Godot's own importer dropped (godotengine/godot#122494: an entry whose key sorts
// after the first one written is never stored), made here from the real project: the chair's cache
// holds only an entry of least key (another mesh's, written first), so the chair's own entry, of
// greater key, is the dropped one. Its users are named with the cause (no "reimport"), the
// conversion is refused by default in one line naming them and the option, and converts with
// --allow-unplaced, the kept texels counted in the summary and the report.
TEST(GodotFbx, DroppedEntryIsRefusedByDefaultAndCountedWhenAllowed) {
  const fs::path bake = ahd_test::test_data("bakes/godot42-vermilion/project");
  if (!fs::exists(bake / "scenes/world.exr")) GTEST_SKIP() << "no " << bake / "scenes/world.exr";
  const fs::path dir = ahd_test::temp_dir("godot_fbx_dropped");
  fs::copy(bake, dir / "project", fs::copy_options::recursive);
  const fs::path models = dir / "project/assets/models";
  std::vector<uint8_t> first = ahd_test::slurp(models / "apartments/doorframe/doorframe.glb.unwrap_cache");
  ASSERT_GT(first.size(), 20u);
  std::fill(first.begin() + 4, first.begin() + 20, uint8_t(0));  // the least key
  write(models / "chair/chair.glb.unwrap_cache", first);
  const std::string dropped_from = "chair.glb.unwrap_cache";
  const fs::path scenes = dir / "project/scenes";
  const GodotSceneMeshes g = load_godot_scene((scenes / "world.tscn").string());
  ASSERT_FALSE(g.unplaced.empty()) << testing::PrintToString(g.notes);
  EXPECT_EQ(g.scene.instances.size() + g.unplaced.size(), 55u);
  const GodotUnplacedUser& u = g.unplaced.front();
  EXPECT_TRUE(contains(u.why, dropped_from + " has no entry for mesh")) << u.why;
  EXPECT_TRUE(contains(u.why, "godotengine/godot#122494")) << u.why;
  EXPECT_FALSE(contains(u.why, "reimport it")) << u.why;

  // Refused by default: one error line naming the user, the cause and the option.
  const auto r = ahd_test::run_cli(
      {"convert", (scenes / "world.exr").string(), "-o", (dir / "o/w.ktx2").string(), "--levels", "1"});
  EXPECT_NE(r.exit_code, 0) << r.output;
  size_t error_lines = 0;
  for (size_t at = r.output.find("ahdpack: error:"); at != std::string::npos;
       at = r.output.find("ahdpack: error:", at + 1))
    ++error_lines;
  EXPECT_EQ(error_lines, 1u) << r.output;
  EXPECT_TRUE(contains(r.output, "lightmap users cannot be placed from the project")) << r.output;
  EXPECT_TRUE(contains(r.output, u.node)) << r.output;
  EXPECT_TRUE(contains(r.output, "godotengine/godot#122494")) << r.output;
  EXPECT_TRUE(contains(r.output, "--allow-unplaced converts the other " + std::to_string(55 - g.unplaced.size())))
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "o/w.json"));

  // With --allow-unplaced: converted, the unplaced users' lit texels kept and counted.
  const auto ok = ahd_test::run_cli({"convert", (scenes / "world.exr").string(), "--allow-unplaced", "-o",
                                     (dir / "o/w.ktx2").string(), "--levels", "1"});
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const std::string tag = std::to_string(g.unplaced.size()) + " unplaced user(s) on page 0: ";
  const size_t at = ok.output.find(tag);
  ASSERT_NE(at, std::string::npos) << ok.output;
  const long kept = std::strtol(ok.output.c_str() + at + tag.size(), nullptr, 10);
  EXPECT_GT(kept, 0) << ok.output;
  EXPECT_TRUE(contains(ok.output, "godot scene: lightmap user " + u.node + " left out: ")) << ok.output;
  const std::string report = ahd_test::read_text(dir / "o/w.report.json");
  EXPECT_TRUE(contains(report, tag + std::to_string(kept) + " lit texels kept")) << report.substr(0, 2000);
  fs::remove_all(dir);
}

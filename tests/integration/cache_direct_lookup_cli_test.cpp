// Issue 44: the cache's direct lookup (a rerun of a command checks what it probed, hashes what it
// read and finds the entry without reading the input: docs/asset-cook.md "The key and the cache")
// never worked for a baker's set or a Godot project: their inputs records hold probes of absent files
// (type -1), which the record reader refused, so every rerun read and decoded the input again. Now
// the rerun is a hit that reads nothing — no detection notes are printed, they come from reading —
// and Godot's existence tests are probes too: a mesh's .import appearing afterwards makes the next
// run read the input again instead of serving the entry. Integration tests (they run the CLI).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.h"
#include "layout_test_scene.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

}  // namespace

TEST(CacheDirectLookupCli, GodotProjectRerunReadsNothingUntilAProbedFileAppears) {
  const fs::path src = ahd_test::test_data("godot/corpus/gltf");
  AHD_REQUIRE_DATA(src / "project.godot");
  const fs::path d = ahd_test::temp_dir("cache_direct_godot");
  fs::copy(src, d / "p", fs::copy_options::recursive);
  const std::vector<std::string> args = {"convert", (d / "p" / "world.exr").string(), "-o", (d / "out" / "w.ktx2").string(),
                                         "--cache", (d / "cache").string(), "--profile", "uncompressed", "--levels", "1"};
  const auto first = ahd_test::run_cli(args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  ASSERT_TRUE(contains(first.output, "godot scene: ")) << first.output;  // the detection notes of a read
  const auto again = ahd_test::run_cli(args);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(contains(again.output, "cache hit ")) << again.output;
  EXPECT_FALSE(contains(again.output, "godot scene: ")) << "the rerun read the input:\n" << again.output;
  EXPECT_FALSE(contains(again.output, "atlas: ")) << again.output;

  // An import file beside a mesh: the Godot reader reads it when present (its options decide the
  // mesh), so the rerun must read the input again, not serve the entry by the old list.
  ASSERT_FALSE(fs::exists(d / "p" / "models" / "rock.glb.import"));
  std::ofstream(d / "p" / "models" / "rock.glb.import") << "[remap]\n\nimporter=\"scene\"\ntype=\"PackedScene\"\n";
  const auto third = ahd_test::run_cli(args);
  EXPECT_TRUE(contains(third.output, "godot scene: ")) << "a probed file appeared but the input was not read:\n" << third.output;
  fs::remove_all(d);
}

// A Bakery set found from its L0 file (layout detection probes the other bakers' absent files).
TEST(CacheDirectLookupCli, BakerSetRerunReadsNothing) {
  const fs::path d = ahd_test::temp_dir("cache_direct_bakery");
  const WorldScene w = world_scene();
  write_bakery_sh(w, (d / "lm").string());
  write_image((d / "n.exr").string(), w.normals);
  const std::vector<std::string> args = {"convert", (d / "lm_L0.hdr").string(), "--normals", (d / "n.exr").string(), "-o",
                                         (d / "out" / "lm.ktx2").string(), "--cache", (d / "cache").string(), "--profile",
                                         "uncompressed", "--levels", "1"};
  const auto first = ahd_test::run_cli(args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  ASSERT_TRUE(contains(first.output, "layout auto: bakery-sh")) << first.output;
  const auto again = ahd_test::run_cli(args);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(contains(again.output, "cache hit ")) << again.output;
  EXPECT_FALSE(contains(again.output, "layout auto: ")) << "the rerun read the input:\n" << again.output;
  fs::remove_all(d);
}

// Damaged or unsuitable Godot SH through the command: the warning on stderr and in the report, and
// --layout plain on a directional stack refused. In-process tests: tests/unit/godot_l1_damage_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "godot_turned_bake.h"
#include "test_data.h"
#include "bakers/baker_layout.h"
#include "bakers/godot/godot_scene.h"
#include "files/file_io.h"
#include "files/profile_file.h"
#include "image/image_io.h"
#include "pipeline/convert.h"
#include "scene/lightmap_raster.h"
#include "scene/placement.h"
#include "godot_l1_damage_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::godot_l1_damage_fixture;


// The command line: the damaged EXR (beside the project's scene) warns on stderr and in the report,
// and still converts; the bake as it is does not warn.
TEST(GodotScene, DenoiserClampedL1WarnsOnStderrAndInTheReport) {
  NEED_BAKE();
  const fs::path d = ahd_test::temp_dir("godot_l1_damage");
  ImageF img = read_image((kScenes / "world.exr").string());
  ASSERT_EQ(img.height, 4 * img.width);
  for (int y = img.width; y < img.height; ++y)  // layers 1-3: L1y, L1z, L1x
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < std::min(3, img.channels); ++c) img.at(x, y)[c] = std::max(img.at(x, y)[c], 0.0f);
  std::vector<std::string> names = {"R", "G", "B", "A"};
  names.resize(size_t(img.channels));
  write_image((d / "world.exr").string(), img, /*half=*/true, names);
  fs::copy_file(kScenes / "world.exr.import", d / "world.exr.import");

  const auto run = [&](const fs::path& exr, const std::string& out) {
    return ahd_test::run_cli({"convert", exr.string(), "--layout", "godot4-unpacked", "--godot-scene",
                              (kScenes / "world.tscn").string(), "-o", (d / out).string(), "--levels", "1"});
  };
  const auto bad = run(d / "world.exr", "bad/w.ktx2");
  ASSERT_EQ(bad.exit_code, 0) << bad.output;
  EXPECT_TRUE(contains(bad.output, "ahdpack: warning: ")) << bad.output;
  EXPECT_TRUE(contains(bad.output, "godotengine/godot#82655")) << bad.output;
  std::vector<uint8_t> b = read_file_bytes((d / "bad" / "w.report.json").string());
  nlohmann::json j = nlohmann::json::parse(b.begin(), b.end());
  ASSERT_FALSE(j.at("warnings").empty());
  EXPECT_TRUE(contains(j.at("warnings")[0].get<std::string>(), "no negative value")) << j.at("warnings");
  for (int k = 0; k < 3; ++k) EXPECT_EQ(j.at("input_sh").at("l1_negative_fraction")[k].get<double>(), 0.0) << k;

  const auto good = run(kScenes / "world.exr", "good/w.ktx2");
  ASSERT_EQ(good.exit_code, 0) << good.output;
  EXPECT_FALSE(contains(good.output, "warning")) << good.output;
  b = read_file_bytes((d / "good" / "w.report.json").string());
  j = nlohmann::json::parse(b.begin(), b.end());
  EXPECT_TRUE(j.at("warnings").empty()) << j.at("warnings");
  for (int k = 0; k < 3; ++k) EXPECT_GT(j.at("input_sh").at("l1_negative_fraction")[k].get<double>(), 0.1) << k;
  fs::remove_all(d);
}

// `--layout plain` on Godot's stacked L0 + L1 layers: one line naming the layout and the remedy,
// nothing written.
TEST(GodotScene, LayoutPlainOnTheDirectionalStackIsRefusedNamingTheLayout) {
  NEED_BAKE();
  const fs::path d = ahd_test::temp_dir("godot_plain_stack");
  const std::string exr = (kScenes / "world.exr").string();
  const auto r = ahd_test::run_cli({"convert", exr, "--layout", "plain", "-o", (d / "w.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "ahdpack: error: " + exr + ": is a Godot directional SH atlas, 1 page(s) x (L0 + three L1 layers)"))
      << r.output;
  EXPECT_TRUE(contains(r.output, "detected: godot4-unpacked")) << r.output;
  EXPECT_TRUE(contains(r.output, "use --layout auto or --layout godot4-unpacked")) << r.output;
  EXPECT_FALSE(fs::exists(d / "w.json"));
  // A plain lightmap without the import file still converts as plain.
  ImageF one(8, 8, 3);
  for (float& v : one.data) v = 0.5f;
  write_image((d / "plain.exr").string(), one);
  const auto ok = ahd_test::run_cli({"convert", (d / "plain.exr").string(), "--layout", "plain", "-o", (d / "p.ktx2").string()});
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  fs::remove_all(d);
}

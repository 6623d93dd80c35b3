// Bad or unsuitable data is said, not converted in silence (issue 40): the real Godot 4.2 bake of
// tests/data/bakes/godot42-vermilion converts without a warning; the same bake with its L1
// clamped at 0 — what Godot's denoiser did to directional bakes, godotengine/godot#82655 — and
// the bake with normals that are not its own are warned about, with the figures in the report.
// `--layout plain` on the Godot stack is refused naming the detected layout and the remedy.
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

namespace fs = std::filesystem;
using namespace ahd;

namespace {

const fs::path kScenes = ahd_test::test_data("bakes/godot42-vermilion") / "project" / "scenes";

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

#define NEED_BAKE() \
  if (!fs::exists(kScenes / "world.tscn")) GTEST_SKIP() << "no " << kScenes / "world.tscn"

// The real bake read as convert reads it (the scene's normals), the normals turned about x by
// `degrees`.
ShImage real_bake(double degrees) { return ahd_test::read_turned_bake(kScenes, degrees).sh; }

// Negative L1 set to 0, as the denoiser left it.
void clamp_l1(ShImage* sh) {
  for (size_t i = 0; i < sh->texels(); ++i)
    for (int j = 3; j < 12; ++j) sh->texel(i)[j] = std::max(sh->texel(i)[j], 0.0f);
}

PipelineResult convert_one(const ShImage& sh) {
  PipelineOptions opt;
  opt.max_levels = 1;
  return run_conversion(sh, load_profile("uncompressed"), opt);
}

bool has_warning(const PipelineResult& r, const std::string& what) {
  for (const std::string& w : r.warnings)
    if (contains(w, what)) return true;
  return false;
}

void print_figures(const char* what, const PipelineResult& r) {
  std::printf("%s: L1 negative y %.3f z %.3f x %.3f, zero y %.3f z %.3f x %.3f; rules %.4f; %zu warning(s)\n", what,
              double(r.l1.negative[0]) / double(r.l1.values[0]), double(r.l1.negative[1]) / double(r.l1.values[1]),
              double(r.l1.negative[2]) / double(r.l1.values[2]), double(r.l1.zero[0]) / double(r.l1.values[0]),
              double(r.l1.zero[1]) / double(r.l1.values[1]), double(r.l1.zero[2]) / double(r.l1.values[2]),
              rules_share(r.fit_stats), r.warnings.size());
}

}  // namespace

TEST(GodotL1, RealBakeIsSoundAndItsDenoiserClampedOrMisorientedFormsAreWarned) {
  NEED_BAKE();
  ShImage sh = real_bake(0);
  const PipelineResult sound = convert_one(sh);
  print_figures("sound", sound);
  EXPECT_TRUE(sound.warnings.empty()) << sound.warnings.front();
  for (int k = 0; k < 3; ++k) EXPECT_GT(sound.l1.negative[k], sound.l1.values[k] / 10) << k;  // both signs in every layer
  EXPECT_LE(rules_share(sound.fit_stats), kRulesShareWarned);

  clamp_l1(&sh);
  const PipelineResult clamped = convert_one(sh);
  print_figures("clamped", clamped);
  EXPECT_EQ(clamped.l1.negative[0] + clamped.l1.negative[1] + clamped.l1.negative[2], 0u);
  EXPECT_TRUE(has_warning(clamped, "no negative value in any layer")) << ::testing::PrintToString(clamped.warnings);
  EXPECT_TRUE(has_warning(clamped, "godotengine/godot#82655")) << ::testing::PrintToString(clamped.warnings);

  const PipelineResult turned = convert_one(real_bake(90));
  print_figures("normals turned 90 deg", turned);
  EXPECT_TRUE(has_warning(turned, "horizon-tilted and negative-I_z rules fired")) << ::testing::PrintToString(turned.warnings);
  EXPECT_FALSE(has_warning(turned, "no negative value"));  // its L1 is sound: the normals are not
}

TEST(GodotL1, FewTexelsOrNoL1AreNotJudged) {
  L1Figures f;
  f.values[0] = f.values[1] = f.values[2] = 30;
  f.zero[0] = 30;
  FitStats s;
  EXPECT_TRUE(sh_input_warnings(f, s, 4).empty());  // 10 texels: too few
  f.values[0] = f.values[1] = f.values[2] = 3000;
  EXPECT_TRUE(sh_input_warnings(f, s, 4).empty());  // 1 % exact zeros: not the clamp's share
  f.zero[0] = 450;
  EXPECT_TRUE(sh_input_warnings(f, s, 4).empty());  // 15 %: as many as sound bakes have (vermilion's L1y)
  f.zero[0] = 900;
  EXPECT_EQ(sh_input_warnings(f, s, 4).size(), 1u);  // 30 % zeros in L1y, no negative value
  EXPECT_TRUE(sh_input_warnings(f, s, 1).empty());  // no L1 (a plain lightmap)
  f.zero[0] = f.zero[1] = f.zero[2] = 3000;
  EXPECT_TRUE(sh_input_warnings(f, s, 4).empty());  // L1 zero everywhere: no direction, not damage
  f.zero[1] = f.zero[2] = 0, f.negative[2] = 1;
  EXPECT_TRUE(sh_input_warnings(f, s, 4).empty());  // one negative value: not clamped
  s.covered = 1000, s.dir_clamped = 20, s.negative_iz = 11;
  ASSERT_EQ(sh_input_warnings(f, s, 4).size(), 1u);  // 3.1 % > 3 %
  EXPECT_TRUE(contains(sh_input_warnings(f, s, 4)[0], "3.1 % of covered texels (20 + 11 of 1000"));
  s.negative_iz = 10;
  EXPECT_TRUE(sh_input_warnings(f, s, 4).empty());  // 3.0 %: not more than 3 %
}

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

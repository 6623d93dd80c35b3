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
#include "godot_l1_damage_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::godot_l1_damage_fixture;

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

// Issue 40's further corpus rows, whole projects in tests/data/godot/corpus/ made by
// tests/tools/godot/gen/corpus/make.sh (README there and in the corpus folder):
// - `fbx`: two .fbx instances (Godot 4.6's own FBX importer read them) imported with Static
//   Lightmaps, each NAME.fbx.unwrap_cache written as Godot's scene importer writes it (the key of
//   ImporterMesh::lightmap_unwrap_cached, entries collected as _generate_meshes collects them);
// - `fbx_dropped`: one .fbx of three meshes whose cache holds only the entry Godot keeps — the
//   other two keys sort after the first one written, and Godot drops them (godotengine/godot#122494);
// - `godot40`: the `gltf` project as a Godot 4.0 pre-release saves it (`ExtResource( "1" )` with
//   spaces, resource format 4 .lmbake with 4.0's properties, raw L1, no GODOT_single_root).
// Each converts with the README's one-line recipe (the dropped one with --allow-unplaced, after a
// refusal naming each user), every user placed, every lit texel within Godot's ring of the
// coverage, the fit's rules firing on at most 3 % of the covered texels. Figures: docs/godot.md
// "The corpus".
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "bakers/godot/godot_lmbake.h"
#include "bakers/godot/godot_scene.h"
#include "bakers/godot/godot_unwrap_cache.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "godot_corpus_recipe.h"
#include "scene/coverage_check.h"
#include "test_data.h"

namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

struct WildProject {
  const char* name;
  const char* exr;  // below tests/data
  int users;
  int ring;  // Godot's dilation ring as ahdpack allows it (scene/coverage_check.h)
};

const WildProject kWild[] = {
    {"fbx", "godot/corpus/fbx/scenes/room.exr", 2, ahd::kGodot44Dilation},
    {"godot40", "godot/corpus/godot40/world.exr", 2, ahd::kDilation},
};

void PrintTo(const WildProject& p, std::ostream* os) { *os << p.name; }

class GodotCorpusWild : public testing::TestWithParam<WildProject> {};

TEST_P(GodotCorpusWild, ConvertsWithTheOneLineRecipeEveryUserPlacedLitWithinTheRingRulesRare) {
  const WildProject& p = GetParam();
  const fs::path exr = ahd_test::test_data(p.exr);
  AHD_REQUIRE_DATA(exr);
  const std::string scene = ahd::find_godot_scene(exr.string());
  ASSERT_FALSE(scene.empty()) << exr;
  const ahd::GodotSceneMeshes g = ahd::load_godot_scene(scene);
  EXPECT_EQ(g.users, p.users);
  EXPECT_EQ(g.scene.instances.size(), size_t(p.users));
  EXPECT_TRUE(g.unplaced.empty());
  // Each FBX mesh finds its cache entry by Godot's key, not by its triangles (said in a note).
  for (const std::string& n : g.notes) EXPECT_FALSE(contains(n, "by its triangles")) << n;

  const fs::path dir = ahd_test::temp_dir(std::string("godot_corpus_wild_") + p.name);
  const ahd_test::Converted c = ahd_test::convert_recipe(exr, dir);
  ASSERT_EQ(c.cli.exit_code, 0) << c.cli.output;
  EXPECT_EQ(c.pages, 1) << c.cli.output;
  EXPECT_GT(c.covered, 0u);
  EXPECT_EQ(c.outside, 0u) << c.cli.output;
  EXPECT_TRUE(contains(c.cli.output, std::to_string(p.users) + " of " + std::to_string(p.users) +
                                         " lightmap users placed"))
      << c.cli.output;
  ASSERT_GT(c.fit_covered, 0u) << c.cli.output;
  EXPECT_LE(c.rules_pct(), 3.0) << c.cli.output;
  std::printf(
      "corpus: %s: %d page(s), %zu of %d users placed, %zu covered, %zu lit, %zu lit beyond %d texels, "
      "min IoU %.3f; rules: horizon-tilted %zu + negative I_z %zu of %zu covered = %.2f %%\n",
      p.name, c.pages, g.scene.instances.size(), g.users, c.covered, c.lit, c.outside, p.ring, c.iou_min, c.tilted,
      c.negative_iz, c.fit_covered, c.rules_pct());
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Projects, GodotCorpusWild, testing::ValuesIn(kWild),
                         [](const testing::TestParamInfo<WildProject>& i) { return std::string(i.param.name); });

// The 4.0 pre-release project is what it claims to be: the spaced text syntax, a format-4 .lmbake
// of engine 4.0 without 4.4's packed-L1 property, its users placed by it; the layout comes out raw.
TEST(GodotCorpusWildFiles, Godot40ProjectHasThePreReleaseSpellingAndFormat4) {
  const fs::path dir = ahd_test::test_data("godot/corpus/godot40");
  AHD_REQUIRE_DATA(dir / "world.lmbake");
  const std::string tscn = ahd_test::read_text(dir / "world.tscn");
  EXPECT_TRUE(contains(tscn, "instance=ExtResource( \"1\" )")) << tscn;
  EXPECT_TRUE(contains(tscn, "light_data = ExtResource( \"3\" )")) << tscn;
  const ahd::GodotLightmapData lm = ahd::read_godot_lmbake((dir / "world.lmbake").string());
  EXPECT_EQ(lm.format, 4);
  EXPECT_EQ(lm.engine_major, 4);
  EXPECT_EQ(lm.engine_minor, 0);
  EXPECT_FALSE(lm.has_packed_directional);
  EXPECT_TRUE(lm.uses_spherical_harmonics);
  ASSERT_EQ(lm.users.size(), 2u);
  EXPECT_EQ(lm.users[0].path, "../Rock/rock/RockMesh");
  EXPECT_EQ(lm.users[1].path, "../Post/post/PostMesh");
}

// A cache missing entries Godot itself dropped: tiles.fbx's three meshes are unwrapped in node
// order and only the first entry is kept (the two later keys sort after it). The reader names the
// two users with the cause and the remedy; the recipe is refused in one line naming both and the
// option; with --allow-unplaced the third user is placed from its mesh and the other two users'
// lit texels are kept, counted in the summary and the report, the rules still rare.
TEST(GodotCorpusDropped, RefusedNamingEachUserThenConvertedWithTheCountedFallback) {
  const fs::path project = ahd_test::test_data("godot/corpus/fbx_dropped");
  AHD_REQUIRE_DATA(project / "level.exr");
  const std::vector<ahd::GodotUnwrapEntry> cache =
      ahd::read_godot_unwrap_cache((project / "models/tiles.fbx.unwrap_cache").string());
  ASSERT_EQ(cache.size(), 1u);

  const ahd::GodotSceneMeshes g = ahd::load_godot_scene((project / "level.tscn").string());
  EXPECT_EQ(g.users, 3);
  ASSERT_EQ(g.scene.instances.size(), 1u);
  EXPECT_EQ(g.scene.instances[0].node, "../Tiles/Rect");
  ASSERT_EQ(g.unplaced.size(), 2u);
  EXPECT_EQ(g.unplaced[0].node, "../Tiles/Short02");
  EXPECT_EQ(g.unplaced[1].node, "../Tiles/Short13");
  for (const ahd::GodotUnplacedUser& u : g.unplaced) {
    EXPECT_TRUE(contains(u.why, "tiles.fbx.unwrap_cache has no entry for mesh")) << u.why;
    EXPECT_TRUE(contains(u.why, "godotengine/godot#122494")) << u.why;
    EXPECT_FALSE(contains(u.why, "reimport it")) << u.why;
  }

  const fs::path dir = ahd_test::temp_dir("godot_corpus_dropped");
  const fs::path exr = project / "level.exr";
  const ahd_test::Converted refused = ahd_test::convert_recipe(exr, dir);
  EXPECT_EQ(refused.cli.exit_code, 1) << refused.cli.output;
  size_t errors = 0;
  for (size_t at = refused.cli.output.find("ahdpack: error:"); at != std::string::npos;
       at = refused.cli.output.find("ahdpack: error:", at + 1))
    ++errors;
  EXPECT_EQ(errors, 1u) << refused.cli.output;
  EXPECT_TRUE(contains(refused.cli.output, "2 of 3 lightmap users cannot be placed")) << refused.cli.output;
  EXPECT_TRUE(contains(refused.cli.output, "../Tiles/Short02")) << refused.cli.output;
  EXPECT_TRUE(contains(refused.cli.output, "../Tiles/Short13")) << refused.cli.output;
  EXPECT_TRUE(contains(refused.cli.output, "--allow-unplaced converts the other 1")) << refused.cli.output;
  EXPECT_FALSE(fs::exists(dir / "level.ktx2"));
  EXPECT_FALSE(fs::exists(dir / "level.report.json"));

  const ahd_test::Converted ok = ahd_test::convert_recipe(exr, dir, {"--allow-unplaced"});
  ASSERT_EQ(ok.cli.exit_code, 0) << ok.cli.output;
  EXPECT_TRUE(contains(ok.cli.output, "1 of 3 lightmap users placed")) << ok.cli.output;
  const std::string tag = "2 unplaced user(s) on page 0: ";
  const size_t at = ok.cli.output.find(tag);
  ASSERT_NE(at, std::string::npos) << ok.cli.output;
  const long kept = std::strtol(ok.cli.output.c_str() + at + tag.size(), nullptr, 10);
  EXPECT_GT(kept, 0) << ok.cli.output;
  const std::string report = ahd_test::read_text(dir / "level.report.json");
  EXPECT_TRUE(contains(report, tag + std::to_string(kept) + " lit texels kept")) << report.substr(0, 2000);
  EXPECT_EQ(ok.outside, 0u) << ok.cli.output;
  ASSERT_GT(ok.fit_covered, 0u);
  EXPECT_LE(ok.rules_pct(), 3.0) << ok.cli.output;
  std::printf(
      "corpus: fbx_dropped: refused by default; --allow-unplaced: 1 of 3 users placed, %ld lit texels kept, "
      "%zu covered, %zu lit, %zu lit beyond %d texels, min IoU %.3f; rules: horizon-tilted %zu + negative I_z %zu "
      "of %zu covered = %.2f %%\n",
      kept, ok.covered, ok.lit, ok.outside, ahd::kGodot44Dilation, ok.iou_min, ok.tilted, ok.negative_iz,
      ok.fit_covered, ok.rules_pct());
  fs::remove_all(dir);
}

}  // namespace

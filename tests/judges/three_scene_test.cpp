// ThreeScene.*: a whole baked scene in three.js. The real Godot 4.2 bake of
// tests/data/bakes/godot42-vermilion is converted as a user would (`convert world.exr --profile
// uncompressed --zstd --iz-scale E/pi`: normal-frame directions, zstd-supercompressed KTX2, I_z
// stored as E/π), its placed scene written by `ahdpack scene` (.glb: world-space meshes, atlas
// lightmap UVs in TEXCOORD_1, each instance's page), and docs/examples/three/scene.html renders it in
// headless Chromium (WebGL2 on SwiftShader) through formats/engine/three/ahd_three.js: array
// textures, the zstd decoder three ships, ahd_to_frame, iz_scale divided, ACES + sRGB. Checked: the
// manifest's instances are the glTF's nodes; the image is not blank; at probe pixels the linear E
// equals the reference decoder of the planes at the texels the pixel's lightmap UV samples.
// Skipped with the reason when chromium, node, the node modules or the bake are missing.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "chromium_page.h"
#include "cli_runner.h"
#include "core/texture.h"
#include "files/manifest_file.h"
#include "pipeline/plane_decode.h"
#include "test_data.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

const fs::path kTools = ahd_test::kSourceDir / "tests" / "tools";
const fs::path kBake = ahd_test::test_data("bakes/godot42-vermilion");

std::vector<uint8_t> bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

// The JSON chunk of a .glb (header 12 bytes, then the chunk's length and type).
nlohmann::json glb_json(const std::vector<uint8_t>& b) {
  if (b.size() < 20 || std::memcmp(b.data(), "glTF", 4) != 0) return nullptr;
  uint32_t len = 0;
  std::memcpy(&len, b.data() + 12, 4);
  if (20 + size_t(len) > b.size()) return nullptr;
  return nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + len);
}

}  // namespace

TEST(ThreeScene, VermilionSceneFromGltfAndZstdArrayPlanesMatchesTheReferenceDecoder) {
  if (ahd_test::chromium_binary().empty()) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  if (!fs::exists(kTools / "node_modules" / "three" / "examples" / "jsm" / "loaders" / "GLTFLoader.js"))
    GTEST_SKIP() << "tests/tools/node_modules/three is missing (scripts/setup.sh runs npm ci there)";
  if (ahd_test::run_shell("command -v node").empty()) GTEST_SKIP() << "node is not installed (scripts/setup.sh installs it)";
  const fs::path exr = kBake / "project" / "scenes" / "world.exr";
  if (!fs::exists(exr)) GTEST_SKIP() << "no " << exr;

  const fs::path dir = ahd_test::temp_dir("three_scene");
  const fs::path site = dir / "site";
  fs::create_directories(site / "ahd");
  fs::create_directory_symlink(kTools / "node_modules" / "three", site / "three");
  fs::create_directory_symlink(ahd_test::kSourceDir / "formats", site / "ahd" / "formats");
  fs::create_directory_symlink(ahd_test::kSourceDir / "docs" / "examples" / "three", site / "page");
  const fs::path conv = site / "conv";
  auto r = run_cli({"convert", exr.string(), "-o", (conv / "world.ktx2").string(), "--profile", "uncompressed", "--zstd",
                    "--iz-scale", "E/pi"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_cli({"scene", exr.string(), "-o", (conv / "world.glb").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // The manifest names every instance the glTF holds, with the page and rectangle of its extras.
  const ahd::Manifest m = ahd::read_manifest_file((conv / "world.json").string());
  EXPECT_EQ(m.direction_frame, "normal-frame");
  EXPECT_NEAR(m.iz_scale, 1 / M_PI, 1e-12);
  const nlohmann::json g = glb_json(bytes_of(conv / "world.glb"));
  ASSERT_TRUE(g.is_object()) << "world.glb is not a glTF binary";
  ASSERT_FALSE(m.instances.empty());
  ASSERT_EQ(g["nodes"].size(), m.instances.size());
  for (size_t i = 0; i < m.instances.size(); ++i) {
    const auto& n = g["nodes"][i];
    EXPECT_EQ(n["name"], m.instances[i].node);
    EXPECT_EQ(n["extras"]["ahd_page"], m.instances[i].page);
    EXPECT_DOUBLE_EQ(n["extras"]["ahd_uv_scale"][0].get<double>(), m.instances[i].scale[0]);
    EXPECT_DOUBLE_EQ(n["extras"]["ahd_uv_offset"][1].get<double>(), m.instances[i].offset[1]);
  }

  std::ofstream(dir / "check.js")
      << "for (let i = 0; i < 400 && !window.ahdReady; ++i) await new Promise((r) => setTimeout(r, 25));\n"
         "if (!window.ahdReady) throw new Error('scene.html did not load');\n"
         "return await window.ahdScene({ manifest: '../conv/world.json', gltf: '../conv/world.glb', exposure: 4.0 });\n";
  const fs::path result = dir / "result.json", shot = dir / "scene.png";
  const std::string log = ahd_test::run_chromium_page({.serve = site,
                                                      .url = "{origin}/page/scene.html",
                                                      .script = dir / "check.js",
                                                      .out = result,
                                                      .screenshot = shot,
                                                      .timeout_seconds = 120});
  std::ifstream rf(result);
  ASSERT_TRUE(rf) << "no result from chromium_cdp.mjs: " << log;
  const nlohmann::json j = nlohmann::json::parse(rf);
  ASSERT_FALSE(j.contains("error")) << j.dump().substr(0, 4000);
  EXPECT_TRUE(j["exceptions"].empty()) << j["exceptions"].dump();
  const auto& run = j["result"];
  ASSERT_TRUE(run.is_object()) << j.dump().substr(0, 4000);
  EXPECT_EQ(run["meshes"].get<size_t>(), m.instances.size());
  EXPECT_EQ(run["frame"], "normal-frame");

  // Not blank: the scene covers a good part of the frame, with contrast (8-bit display values).
  std::printf("three.js scene: %dx%d, %zu meshes, lit fraction %.3f, mean %.1f, stddev %.1f, %zu probes; screenshot %s\n",
              run["width"].get<int>(), run["height"].get<int>(), run["meshes"].get<size_t>(),
              run["litFraction"].get<double>(), run["mean"].get<double>(), run["stddev"].get<double>(),
              run["probes"].size(), shot.c_str());
  EXPECT_GT(run["litFraction"].get<double>(), 0.15);
  EXPECT_GT(run["stddev"].get<double>(), 5.0);

  // Probes. With the shading normal = the frame's normal (no normal map), n = (0, 0, 1) in the
  // normal frame, so E = Ca + d'.z·(I_z − Ca)/d'.z = I_z for any filtered direction and ratio: the
  // reference is the bilinear filter of the decoded iz plane (layer = the probe's page, level 0,
  // texel centres at (i + 0.5)/W, row 0 = v 0) divided by iz_scale. Tolerance: a GPU's bilinear
  // weights need not be exact (8 fractional bits in many samplers; SwiftShader's measured 1.75e-7):
  // |gpu − ref| <= 1e-3 · the 4 texels' largest E + 1e-5, and within the 4 texels' range (same slack).
  ASSERT_GE(run["probes"].size(), 50u);
  std::vector<ahd::DecodedPlanes> pages;
  for (uint32_t layer = 0; layer < m.layers; ++layer) {
    std::vector<ahd::Plane> planes;
    for (const auto& mp : m.planes)
      planes.push_back({mp.name, ahd::texture_layer(ahd::read_manifest_plane((conv / "world.json").string(), mp), layer)});
    pages.push_back(ahd::decode_planes(planes, m.ratio_form == ahd::RatioForm::Rgb, 0));
  }
  size_t bad = 0;
  double worst = 0;
  for (const auto& p : run["probes"]) {
    const int page = p["page"];
    ASSERT_TRUE(page >= 0 && page < int(pages.size()));
    const ahd::DecodedPlanes& d = pages[size_t(page)];
    const double fx = p["uv"][0].get<double>() * d.width - 0.5, fy = p["uv"][1].get<double>() * d.height - 0.5;
    const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    const double ax = fx - x0, ay = fy - y0;
    const auto at = [&](int x, int y, int c) {
      x = std::clamp(x, 0, d.width - 1), y = std::clamp(y, 0, d.height - 1);
      return double(d.iz[(size_t(y) * d.width + x) * 3 + c]) / m.iz_scale;
    };
    for (int c = 0; c < 3; ++c) {
      const double t[4] = {at(x0, y0, c), at(x0 + 1, y0, c), at(x0, y0 + 1, c), at(x0 + 1, y0 + 1, c)};
      const double ref = (t[0] * (1 - ax) + t[1] * ax) * (1 - ay) + (t[2] * (1 - ax) + t[3] * ax) * ay;
      const double hi = *std::max_element(t, t + 4), lo = *std::min_element(t, t + 4);
      const double tol = 1e-3 * std::max(hi, 0.0) + 1e-5, gpu = p["e"][size_t(c)].get<double>();
      const double err = std::max({std::fabs(gpu - ref), lo - gpu, gpu - hi});
      worst = std::max(worst, err / std::max(hi, 1e-3));
      if (err > tol && bad++ < 5)
        ADD_FAILURE() << "probe pixel (" << p["x"] << "," << p["y"] << ") page " << page << " uv (" << p["uv"][0] << ","
                      << p["uv"][1] << ") channel " << c << ": three.js " << gpu << ", reference " << ref << " (texels "
                      << lo << ".." << hi << ")";
    }
  }
  std::printf("probes: worst difference %.2e of the texels' largest E\n", worst);
  EXPECT_EQ(bad, 0u);
  // AHD_SCENE_SHOT=PATH keeps the screenshot (docs/plots/three-vermilion-scene.png was made so).
  if (const char* keep = std::getenv("AHD_SCENE_SHOT")) fs::copy_file(shot, keep, fs::copy_options::overwrite_existing);
}

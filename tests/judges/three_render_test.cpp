// ThreeRender.*: a real engine consumes ahdpack's files. three.js (npm `three`, pinned in
// tests/tools/package-lock.json) loads a conversion's KTX2 planes with its KTX2Loader
// (formats/engine/three/ahd_three.js), a ShaderMaterial with formats/shaders/ahd_decode.glsl lights
// a quad in headless Chromium (WebGL2 on SwiftShader), and docs/examples/three/render_check.html
// reads the float render target back. Every pixel must equal the reference decoder
// (decode_planes + decode_irradiance) for the same normal — flat (0,0,1) and the built-in detail
// normal — at mip levels 0 and 1, for `uncompressed` (RGBA16F/RG8/R8), `packed-float`, `packed-rgb9e5`
// (B10G11R11 or E5B9G9R9 + RGBA8) and, where the renderer exposes BPTC and RGTC, `pc-bc` (BC6H/BC5/BC4).
// Skipped with the reason when chromium or the node modules are missing (scripts/setup.sh).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "chromium_page.h"
#include "cli_runner.h"
#include "core/texture.h"
#include "fit/ahd_decode.h"
#include "files/manifest_file.h"
#include "pipeline/plane_decode.h"
#include "test_data.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

const fs::path kTools = ahd_test::kSourceDir / "tests" / "tools";

// The fragment shader's ahd_detail_normal (formats/engine/three/ahd_three.js), in double.
void detail_normal(double u, double v, double n[3]) {
  const double tau = 6.28318530718;
  n[0] = 0.6 * std::sin(tau * 3.0 * u), n[1] = 0.6 * std::cos(tau * 2.0 * v), n[2] = 1.0;
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int c = 0; c < 3; ++c) n[c] /= len;
}

// The reference decoder's planes of a conversion at `level` (layer 0), as `ahdpack decode` reads them.
ahd::DecodedPlanes reference_planes(const std::string& manifest, int level, ahd::Manifest* m) {
  *m = ahd::read_manifest_file(manifest);
  std::vector<ahd::Plane> planes;
  for (const auto& mp : m->planes) planes.push_back({mp.name, ahd::texture_layer(ahd::read_manifest_plane(manifest, mp), 0)});
  return ahd::decode_planes(planes, m->ratio_form == ahd::RatioForm::Rgb, level);
}

}  // namespace

TEST(ThreeRender, KtxPlanesLitInChromiumMatchTheReferenceDecoder) {
  if (ahd_test::chromium_binary().empty()) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  if (!fs::exists(kTools / "node_modules" / "three" / "examples" / "jsm" / "loaders" / "KTX2Loader.js"))
    GTEST_SKIP() << "tests/tools/node_modules/three is missing (scripts/setup.sh runs npm ci there)";
  if (ahd_test::run_shell("command -v node").empty())
    GTEST_SKIP() << "node is not installed (scripts/setup.sh installs it)";

  const fs::path dir = ahd_test::temp_dir("three_render");
  const fs::path src = dir / "s.exr";
  ASSERT_EQ(run_cli({"sample", "-o", src.string(), "--size", "32"}).exit_code, 0);
  const std::vector<std::string> profiles = {"uncompressed", "packed-float", "packed-rgb9e5", "pc-bc"};
  // The folder the local server shows (the layout render_check.html documents).
  const fs::path site = dir / "site";
  fs::create_directories(site / "ahd");
  fs::create_directory_symlink(kTools / "node_modules" / "three", site / "three");
  fs::create_directory_symlink(ahd_test::kSourceDir / "formats", site / "ahd" / "formats");
  fs::create_directory_symlink(ahd_test::kSourceDir / "docs" / "examples" / "three", site / "page");
  for (const auto& p : profiles) {
    const auto r = run_cli({"convert", src.string(), "-o", (site / "conv" / p / "s.ktx2").string(), "--profile", p});
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  // One browser session renders every profile at levels 0 and 1.
  std::string script =
      "for (let i = 0; i < 400 && !window.ahdReady; ++i) await new Promise((r) => setTimeout(r, 25));\n"
      "if (!window.ahdReady) throw new Error('render_check.html did not load');\nconst out = [];\n";
  for (const auto& p : profiles)
    for (int level : {0, 1})
      script += "out.push(await window.ahdRenderCheck('../conv/" + p + "/s.json', " + std::to_string(level) + "));\n";
  script += "return out;\n";
  std::ofstream(dir / "check.js") << script;
  const fs::path result = dir / "result.json";
  const std::string log = ahd_test::run_chromium_page(
      {.serve = site, .url = "{origin}/page/render_check.html", .script = dir / "check.js", .out = result});
  std::ifstream rf(result);
  ASSERT_TRUE(rf) << "no result from chromium_cdp.mjs: " << log;
  const nlohmann::json j = nlohmann::json::parse(rf);
  ASSERT_FALSE(j.contains("error")) << j.dump().substr(0, 4000);
  EXPECT_TRUE(j["exceptions"].empty()) << j["exceptions"].dump();
  const auto& runs = j["result"];
  ASSERT_EQ(runs.size(), profiles.size() * 2);

  // Tolerances. BC6H, RGBA16F, B10G11R11, RG8, R8 and RGBA8 reach the shader as the exact values our
  // decoder gives (texel centres, no filtering between texels), so the flat normal — E = I_z —
  // must agree to float32 rounding: 1e-4 · max(|ref|, 1) per channel. The detail normal adds
  // SwiftShader's float32 sin/cos and normalize: 1e-3 · max(|ref|, 1). And a GPU decodes
  // BC4/BC5 (RGTC) to 8 bits (within one 8-bit step of the exact palette our decoder uses,
  // tests/judges/gl/rgtc_mesa_test.cpp): for pc-bc the detail value must lie, within 1e-3, in the range
  // the reference takes when the ratio and each hemi-octahedral coordinate move by ±1/255.
  const auto in_range = [](const float iz[3], const float d[3], const float ratio[3], const double n[3], double dz_min,
                           bool rgtc, double lo[3], double hi[3]) {
    for (int c = 0; c < 3; ++c) lo[c] = 1e300, hi[c] = -1e300;
    const double s = std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2]);
    const double px = d[0] / s, py = d[1] / s;  // the octahedral point of d (hemi-oct steps are 2/255 in p)
    const int r = rgtc ? 1 : 0;
    for (int a = -r; a <= r; ++a)
      for (int b = -r; b <= r; ++b)
        for (int q = -r; q <= r; ++q) {
          const double x = px + a * 2.0 / 255, y = py + b * 2.0 / 255;
          const float dd[3] = {float(x), float(y), float(std::max(0.0, 1.0 - std::fabs(x) - std::fabs(y)))};
          float rr[3];
          for (int c = 0; c < 3; ++c) rr[c] = std::clamp(ratio[c] + q / 255.0f, 0.0f, 1.0f);
          double e[3];
          ahd::decode_irradiance(iz, rgtc ? dd : d, rr, n, dz_min, e);
          for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], e[c]), hi[c] = std::max(hi[c], e[c]);
        }
  };
  size_t k = 0;
  for (const auto& p : profiles)
    for (int level : {0, 1}) {
      const auto& run = runs[k++];
      const std::vector<std::string> ext = run["extensions"];
      const bool bc = p == "pc-bc";
      if (bc && (std::find(ext.begin(), ext.end(), "EXT_texture_compression_bptc") == ext.end() ||
                 std::find(ext.begin(), ext.end(), "EXT_texture_compression_rgtc") == ext.end())) {
        std::printf("pc-bc: the renderer lacks BPTC or RGTC (%s); checked uncompressed and packed-float only\n",
                    run["extensions"].dump().c_str());
        continue;
      }
      ahd::Manifest m;
      const ahd::DecodedPlanes ref = reference_planes((site / "conv" / p / "s.json").string(), level, &m);
      ASSERT_EQ(run["width"].get<int>(), ref.width) << p;
      ASSERT_EQ(run["height"].get<int>(), ref.height) << p;
      for (const char* which : {"flat", "detail"}) {
        const std::vector<double> gpu = run[which];
        ASSERT_EQ(gpu.size(), size_t(ref.width) * ref.height * 3);
        double worst = 0, mean_e = 0;
        size_t bad = 0;
        for (int y = 0; y < ref.height; ++y)
          for (int x = 0; x < ref.width; ++x) {
            const size_t i = size_t(y) * ref.width + x;
            double n[3] = {0, 0, 1};
            if (which[0] == 'd') detail_normal((x + 0.5) / ref.width, (y + 0.5) / ref.height, n);
            const bool detail = which[0] == 'd';
            double lo[3], hi[3];
            in_range(&ref.iz[i * 3], &ref.d[i * 3], &ref.ratio[i * 3], n, m.dz_min, bc && detail, lo, hi);
            for (int c = 0; c < 3; ++c) {
              const double g = gpu[i * 3 + c], tol = (detail ? 1e-3 : 1e-4) * std::max(std::fabs(hi[c]), 1.0);
              const double err = g < lo[c] ? lo[c] - g : g > hi[c] ? g - hi[c] : 0.0;
              worst = std::max(worst, err / std::max(std::fabs(hi[c]), 1.0));
              mean_e += hi[c];
              if (err > tol && bad++ < 5)
                ADD_FAILURE() << p << " level " << level << " " << which << " texel (" << x << "," << y << ") channel "
                              << c << ": three.js " << g << ", reference [" << lo[c] << ", " << hi[c] << "]";
            }
          }
        std::printf("%-13s level %d %-6s: worst relative difference beyond the range %.2e (mean E %.3f)\n", p.c_str(), level, which,
                    worst, mean_e / double(gpu.size()));
        EXPECT_EQ(bad, 0u);
      }
    }
}

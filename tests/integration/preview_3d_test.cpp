// Preview3d.*: `ahdpack preview --mesh M.glb` writes view3d.html, which lights the mesh with the
// converted planes in headless Chromium (WebGL2 on SwiftShader, from file://). The test clicks the
// A/B and normal-map controls and checks that the canvas changes each time, clicks a texel of the
// lightmap view at 1:1 and checks the readout against the reference decoder and the source's
// coverage. Without three.js the page is the static one with a note. Skipped when chromium or
// node is missing (scripts/setup.sh installs them).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "chromium_page.h"
#include "cli_runner.h"
#include "core/texture.h"
#include "fit/ahd_decode.h"
#include "files/manifest_file.h"
#include "image/sh_exr.h"
#include "pipeline/plane_decode.h"
#include "test_data.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {


// A folded n×n grid (a ridge along x) with one UV set covering [0,1]² (glTF: v down), as .glb.
void write_glb(const fs::path& path, int n = 9) {
  std::vector<float> pos, uv;
  std::vector<uint16_t> idx;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float u = float(i) / float(n - 1), v = float(j) / float(n - 1);
      pos.insert(pos.end(), {2 * u - 1, 0.4f * (1 - std::fabs(2 * u - 1)), 2 * v - 1});
      uv.insert(uv.end(), {u, v});
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const uint16_t a = uint16_t(j * n + i), b = uint16_t(a + 1), c = uint16_t(a + n), d = uint16_t(c + 1);
      idx.insert(idx.end(), {a, c, b, b, c, d});
    }
  std::string bin(reinterpret_cast<const char*>(pos.data()), pos.size() * 4);
  bin.append(reinterpret_cast<const char*>(uv.data()), uv.size() * 4);
  bin.append(reinterpret_cast<const char*>(idx.data()), idx.size() * 2);
  while (bin.size() % 4) bin += '\0';
  const size_t pb = pos.size() * 4, ub = uv.size() * 4, ib = idx.size() * 2;
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"name", "ridge"}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}}}}}}},
      {"buffers", {{{"byteLength", bin.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", pb}},
                       {{"buffer", 0}, {"byteOffset", pb}, {"byteLength", ub}},
                       {{"buffer", 0}, {"byteOffset", pb + ub}, {"byteLength", ib}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", n * n}, {"type", "VEC3"},
                      {"min", {-1, 0, -1}}, {"max", {1, 0.4, 1}}},
                     {{"bufferView", 1}, {"componentType", 5126}, {"count", n * n}, {"type", "VEC2"}},
                     {{"bufferView", 2}, {"componentType", 5123}, {"count", idx.size()}, {"type", "SCALAR"}}}}};
  std::string js = j.dump();
  while (js.size() % 4) js += ' ';
  auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
  std::string out = "glTF";
  u32(out, 2), u32(out, uint32_t(12 + 8 + js.size() + 8 + bin.size()));
  u32(out, uint32_t(js.size())), out += "JSON", out += js;
  u32(out, uint32_t(bin.size())), out += std::string("BIN\0", 4), out += bin;
  std::ofstream(path, std::ios::binary) << out;
}

// The in-page script: clicks through the controls, samples the WebGL canvas after each, clicks
// texel (TX, TY) of the lightmap view at 1:1 and returns the readout.
const char* kScript = R"JS(
const $ = (id) => document.getElementById(id);
for (let i = 0; i < 200 && document.body.dataset.status === 'loading'; ++i) await new Promise((r) => setTimeout(r, 25));
if (document.body.dataset.status !== 'ok') throw new Error('status: ' + document.body.dataset.status);
const grab = () => {  // the WebGL canvas as 8-bit RGB (preserveDrawingBuffer), via a 2D canvas
  const v = $('view'), c = document.createElement('canvas');
  c.width = v.width; c.height = v.height;
  const ctx = c.getContext('2d');
  ctx.drawImage(v, 0, 0);
  const d = ctx.getImageData(0, 0, c.width, c.height).data, out = [];
  for (let i = 0; i < d.length; i += 4) out.push(d[i], d[i + 1], d[i + 2]);
  return out;
};
const shots = { ahd: grab() };
const click = (id) => { $(id).click(); return grab(); };
shots.sh = click('mode-sh');
shots.diff_sh = click('mode-diff-sh');
shots.plain = click('mode-plain');
shots.diff_plain = click('mode-diff-plain');
shots.ahd_again = click('mode-ahd');
shots.ahd_nm = click('nm');
shots.sh_nm = click('mode-sh');
shots.plain_nm = click('mode-plain');
$('mode-ahd').click(); $('nm').click();
// Mean absolute difference of two shots (8-bit levels), and the AHD shot's luminance histogram.
const diff = (a, b) => { let s = 0; for (let i = 0; i < a.length; ++i) s += Math.abs(a[i] - b[i]); return s / a.length; };
const diffs = {};
for (const k of Object.keys(shots)) diffs[k] = diff(shots.ahd, shots[k]);
diffs.ahd_nm_vs_sh_nm = diff(shots.ahd_nm, shots.sh_nm);
diffs.ahd_nm_vs_plain_nm = diff(shots.ahd_nm, shots.plain_nm);
const hist = new Array(256).fill(0);
for (let i = 0; i < shots.ahd.length; i += 3)
  hist[Math.round((shots.ahd[i] * 2126 + shots.ahd[i + 1] * 7152 + shots.ahd[i + 2] * 722) / 10000)]++;
$('zoom').value = '1'; $('zoom').dispatchEvent(new Event('change'));
// A click inside texel (TX, TY) of the 1:1 view (client coordinates are whole pixels).
const lm = $('lm'), rc = lm.getBoundingClientRect();
lm.dispatchEvent(new MouseEvent('click', { clientX: Math.ceil(rc.left) + TX, clientY: Math.ceil(rc.top) + TY, bubbles: true }));
const readout = JSON.parse($('readout').dataset.texel);
return { diffs, hist, readout, text: $('readout').textContent };
)JS";

}  // namespace

TEST(Preview3d, MeshViewClicksThroughAbAndNormalMapAndReadsTheDecoderValue) {
  if (ahd_test::chromium_binary().empty()) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  if (ahd_test::run_shell("command -v node").empty()) GTEST_SKIP() << "node is not installed (scripts/setup.sh)";
  if (!fs::exists(ahd_test::kSourceDir / "tests" / "tools" / "node_modules" / "three" / "build" / "three.module.js"))
    GTEST_SKIP() << "tests/tools/node_modules/three is missing (scripts/setup.sh runs npm ci there)";
  const fs::path dir = ahd_test::temp_dir("preview3d");
  const fs::path src = dir / "s.exr", glb = dir / "ridge.glb", man = dir / "c" / "s.json", out = dir / "page";
  ASSERT_EQ(run_cli({"sample", "-o", src.string(), "--size", "64"}).exit_code, 0);
  auto r = run_cli({"convert", src.string(), "-o", (dir / "c" / "s.ktx2").string(), "--profile", "pc-bc"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  write_glb(glb);
  r = run_cli({"preview", man.string(), "--source", src.string(), "--mesh", glb.string(), "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"view3d.html", "view3d.js", "view3d_data.js", "three_classic.js"})
    ASSERT_TRUE(fs::exists(out / f)) << f;
  std::ifstream ih(out / "index.html");
  const std::string index((std::istreambuf_iterator<char>(ih)), {});
  EXPECT_NE(index.find("href=\"view3d.html\""), std::string::npos);
  EXPECT_NE(index.find("ridge.glb"), std::string::npos);

  const int tx = 11, ty = 37;  // a covered texel of the sample's left chart
  std::string script = kScript;
  for (const auto& [k, v] : {std::pair{"TX", tx}, std::pair{"TY", ty}})
    for (size_t p; (p = script.find(k)) != std::string::npos;) script.replace(p, 2, std::to_string(v));
  std::ofstream(dir / "click.js") << script;
  const std::string log = ahd_test::run_chromium_page({.url = "file://" + (out / "view3d.html").string(),
                                                      .script = dir / "click.js",
                                                      .out = dir / "r.json",
                                                      .screenshot = dir / "shot.png",
                                                      .timeout_seconds = 60});
  std::ifstream rf(dir / "r.json");
  ASSERT_TRUE(rf) << log;
  const nlohmann::json j = nlohmann::json::parse(rf);
  ASSERT_FALSE(j.contains("error")) << j.dump().substr(0, 3000);
  EXPECT_TRUE(j["exceptions"].empty()) << j["exceptions"].dump();
  const auto& res = j["result"];
  const auto& diffs = res["diffs"];
  const std::vector<int> hist = res["hist"];
  // Not blank: the lit mesh covers a good part of the canvas with many distinct values.
  size_t lit = 0, all = 0;
  for (int l = 0; l < 256; ++l) all += size_t(hist[l]), lit += l > 8 ? size_t(hist[l]) : 0;
  EXPECT_GT(double(lit) / double(all), 0.15);
  EXPECT_GT(std::count_if(hist.begin(), hist.end(), [](int c) { return c > 0; }), 40);
  // Every control changes the picture; going back gives the same picture (drawing is deterministic).
  // With the flat normal AHD and the plain lightmap are the same picture by construction
  // (I(z) = I_z); with the detail normal they must differ, as must AHD and the source SH.
  EXPECT_EQ(diffs["ahd_again"].get<double>(), 0.0);
  EXPECT_EQ(diffs["plain"].get<double>(), 0.0);
  for (const char* k : {"sh", "diff_sh", "diff_plain", "ahd_nm", "ahd_nm_vs_sh_nm", "ahd_nm_vs_plain_nm"}) {
    const double d = diffs[k].get<double>();
    std::printf("canvas change %-18s %.2f (8-bit levels, mean over the canvas)\n", k, d);
    EXPECT_GT(d, 0.05) << k;
  }

  // The readout equals the reference decoder at that texel (level 0), for its five normals.
  const auto& ro = res["readout"];
  ASSERT_EQ(ro["x"].get<int>(), tx) << res["text"];
  ASSERT_EQ(ro["y"].get<int>(), ty);
  ASSERT_EQ(ro["level"].get<int>(), 0);
  const ahd::Manifest m = ahd::read_manifest_file(man.string());
  std::vector<ahd::Plane> planes;
  for (const auto& mp : m.planes) planes.push_back({mp.name, ahd::texture_layer(ahd::read_manifest_plane(man.string(), mp), 0)});
  const ahd::DecodedPlanes p = ahd::decode_planes(planes, m.ratio_form == ahd::RatioForm::Rgb, 0);
  const size_t i = size_t(ty) * p.width + tx;
  const auto normals = ro["normals"].get<std::vector<std::vector<double>>>();
  const auto es = ro["e"].get<std::vector<std::vector<double>>>();
  ASSERT_EQ(normals.size(), 5u);
  for (size_t k = 0; k < normals.size(); ++k) {
    double e[3];
    ahd::decode_irradiance(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], normals[k].data(), m.dz_min, e);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(es[k][c], e[c], 1e-9 * std::max(1.0, std::fabs(e[c]))) << "normal " << k;
  }
  EXPECT_GT(std::fabs(es[1][0] - es[2][0]), 1e-3);  // the tilts differ: a directional texel
  const ahd::ShImage sh = ahd::read_canonical_sh(src.string());
  EXPECT_EQ(ro["coverage"].get<int>(), int(sh.coverage[i]));
  EXPECT_EQ(sh.coverage[i], 1);
  EXPECT_TRUE(ro["rules"].is_array());
  EXPECT_NE(res["text"].get<std::string>().find("covered"), std::string::npos);
}

TEST(Preview3d, WithoutThreeTheStaticPageSaysWhy) {
  const fs::path dir = ahd_test::temp_dir("preview3d_none");
  ASSERT_EQ(run_cli({"sample", "-o", (dir / "s.exr").string(), "--size", "16"}).exit_code, 0);
  ASSERT_EQ(run_cli({"convert", (dir / "s.exr").string(), "-o", (dir / "c" / "s.ktx2").string()}).exit_code, 0);
  const std::string cmd = "AHD_THREE_DIR='" + (dir / "no-three").string() + "' '" + AHD_CLI_PATH + "' preview '" +
                          (dir / "c" / "s.json").string() + "' -o '" + (dir / "page").string() + "' 2>&1; echo rc=$?";
  const std::string o = ahd_test::run_shell(cmd);
  EXPECT_NE(o.find("rc=0"), std::string::npos) << o;
  std::ifstream ih(dir / "page" / "index.html");
  const std::string index((std::istreambuf_iterator<char>(ih)), {});
  EXPECT_NE(index.find("3D view not written: three.js not found"), std::string::npos) << index.substr(0, 3000);
  EXPECT_EQ(index.find("href=\"view3d.html\""), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "page" / "view3d.html"));
  EXPECT_FALSE(fs::exists(dir / "page" / "three_classic.js"));
}

TEST(Preview3d, BadMeshIsOneErrorLineAndNoFolder) {
  // Without three.js the page is the static one and the mesh is never read (WithoutThree… above).
  if (!fs::exists(ahd_test::kSourceDir / "tests" / "tools" / "node_modules" / "three" / "build" / "three.module.js"))
    GTEST_SKIP() << "tests/tools/node_modules/three is missing (scripts/setup.sh runs npm ci there)";
  const fs::path dir = ahd_test::temp_dir("preview3d_bad");
  ASSERT_EQ(run_cli({"sample", "-o", (dir / "s.exr").string(), "--size", "16"}).exit_code, 0);
  ASSERT_EQ(run_cli({"convert", (dir / "s.exr").string(), "-o", (dir / "c" / "s.ktx2").string()}).exit_code, 0);
  std::ofstream(dir / "junk.glb") << "not a glb";
  const auto r = run_cli({"preview", (dir / "c" / "s.json").string(), "--mesh", (dir / "junk.glb").string(), "-o",
                          (dir / "page").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_EQ(r.output.rfind("ahdpack: error: ", 0), 0u) << r.output;
  EXPECT_FALSE(fs::exists(dir / "page"));
}

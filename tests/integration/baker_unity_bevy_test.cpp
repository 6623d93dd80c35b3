// Issue 42: Unity, Bevy and plain lightmaps as those engines give them to a user.
// - Unity: two directional pages (Lightmap-0, Lightmap-1) in Unity's layout with a flat fill of
//   the unused atlas space, the scene's meshes as the editor script (addons/unity/) writes them (one
//   glTF node per renderer, UV2 as TEXCOORD_1) with its placement JSON, and the scene's YAML. The
//   renderers of page 1 are placed from the file name; a mesh whose UVs fill the square is refused
//   (it lies on the fill); the right placement is accepted.
// - Bevy: the Cornell box sample's KTX2 lightmaps (tests/data/bevy/, MIT/Apache-2.0) convert per
//   object with --mesh CornellBox.glb --node NAME, no --allow-mismatch, the stored plane equal to
//   the input at the input's scale; a job file converts all three, byte for byte the same.
// - Plain: a lone RGB EXR converts as plain with no flag, at the input's scale.
// The README's recipes are the commands these tests run (BakerRecipes.ReadmeHoldsTheTestedCommands).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fixture_writers.h"
#include "cli_runner.h"
#include "test_data.h"
#include "files/file_io.h"
#include "files/manifest_file.h"
#include "image/image_io.h"
#include "scene/coverage_check.h"
#include "scene/lightmap_raster.h"
#include "scene/mesh_io.h"
#include "scene/placement.h"
#include "scene/placement_io.h"

namespace fs = std::filesystem;
using namespace ahd;

namespace {

// The README's recipes, run as written (`ahdpack` replaced by the built binary) in a folder holding
// the files they name.
const char* const kUnityRecipe =
    "ahdpack convert Lightmap-1_comp_light.exr --mesh Scene.ahdpack.gltf --placement Scene.ahdpack-placement.json "
    "-o out/lightmap-1.ktx2";
const char* const kBevyRecipe =
    "ahdpack convert CornellBox-Large.zstd.ktx2 --mesh CornellBox.glb --node large_box -o out/large.ktx2";
const char* const kBevyJobsRecipe = "ahdpack convert --jobs cornell.jobs.json -o out/";
const char* const kPlainRecipe = "ahdpack convert lightmap.exr -o out/lightmap.ktx2";

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Runs a recipe (or any ahdpack command line) in `dir`: its output and exit code.
ahd_test::CliResult run_in(const fs::path& dir, const std::string& command) {
  const std::string cmd = command.substr(std::string("ahdpack").size());
  const std::string out =
      ahd_test::run_shell("cd '" + dir.string() + "' && '" + AHD_CLI_PATH + "'" + cmd + " 2>&1; echo \"EXIT=$?\"");
  ahd_test::CliResult r;
  const size_t at = out.rfind("EXIT=");
  r.output = out.substr(0, at);
  if (at != std::string::npos) r.exit_code = std::atoi(out.c_str() + at + 5);
  return r;
}

// One quad per node in world space (as the editor script writes: vertices already transformed,
// x negated), its lightmap UVs (TEXCOORD_1; TEXCOORD_0 the same) filling the unit square, as
// Unity's per-renderer UV2 does before lightmapScaleOffset moves it into the atlas.
void write_quads_gltf(const std::string& path, const std::vector<std::pair<std::string, float>>& nodes) {
  std::vector<uint8_t> buf;
  std::ostringstream views, accessors, jnodes, meshes;
  size_t view = 0;
  const auto add = [&](const void* p, size_t bytes) {
    while (buf.size() % 4) buf.push_back(0);
    views << (view ? "," : "") << R"({"buffer":0,"byteOffset":)" << buf.size() << R"(,"byteLength":)" << bytes << "}";
    buf.insert(buf.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + bytes);
    return view++;
  };
  for (size_t k = 0; k < nodes.size(); ++k) {
    const float x = -nodes[k].second;  // the script negates x
    const std::vector<float> pos = {x, 0, 0, x - 1, 0, 0, x - 1, 0, 1, x, 0, 1};
    const std::vector<float> nrm = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
    const std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};  // glTF v down: (u, 1 − v)
    const std::vector<uint32_t> idx = {0, 2, 1, 0, 3, 2};
    const size_t a = add(pos.data(), 48), n = add(nrm.data(), 48), t = add(uv.data(), 32), i = add(idx.data(), 24);
    accessors << (k ? "," : "") << R"({"bufferView":)" << a << R"(,"componentType":5126,"count":4,"type":"VEC3","min":[)"
              << x - 1 << R"(,0,0],"max":[)" << x << R"(,0,1]},{"bufferView":)" << n
              << R"(,"componentType":5126,"count":4,"type":"VEC3"},{"bufferView":)" << t
              << R"(,"componentType":5126,"count":4,"type":"VEC2"},{"bufferView":)" << i
              << R"(,"componentType":5125,"count":6,"type":"SCALAR"})";
    jnodes << (k ? "," : "") << R"({"name":")" << nodes[k].first << R"(","mesh":)" << k << "}";
    meshes << (k ? "," : "") << R"({"name":"Quad","primitives":[{"attributes":{"POSITION":)" << a << R"(,"NORMAL":)" << n
           << R"(,"TEXCOORD_0":)" << t << R"(,"TEXCOORD_1":)" << t << R"(},"indices":)" << i << "}]}";
  }
  std::ofstream f(path);
  f << R"({"asset":{"version":"2.0","generator":"ahdpack AhdpackLightmapExport.cs"},"scene":0,"scenes":[{"nodes":[)";
  for (size_t k = 0; k < nodes.size(); ++k) f << (k ? "," : "") << k;
  f << R"(]}],"nodes":[)" << jnodes.str() << R"(],"meshes":[)" << meshes.str() << R"(],"buffers":[{"byteLength":)"
    << buf.size() << R"(,"uri":"data:application/octet-stream;base64,)" << ahd_test::base64(buf) << R"("}],"bufferViews":[)"
    << views.str() << R"(],"accessors":[)" << accessors.str() << "]}";
}

// The scene: four renderers, two per lightmap page, each scaled into its own atlas rectangle.
struct Renderer {
  const char* name;
  int page;
  double scale, offset[2];
};
const Renderer kRenderers[] = {{"Floor", 0, 0.375, {0.0625, 0.0625}},
                               {"Wall", 0, 0.375, {0.5625, 0.5625}},
                               {"Crate", 1, 0.375, {0.0625, 0.5625}},
                               {"Roof", 1, 0.375, {0.5625, 0.0625}}};
constexpr int kPage = 64;

// The placement file as the editor script writes it (Renderer.lightmapIndex, lightmapScaleOffset).
void write_placement_json(const std::string& path) {
  std::ofstream f(path);
  f << "{\"placements\": [";
  for (size_t k = 0; k < 4; ++k) {
    const Renderer& r = kRenderers[k];
    f << (k ? "," : "") << "\n  {\"node\": \"" << r.name << "\", \"page\": " << r.page << ", \"scale\": [" << r.scale << ", "
      << r.scale << "], \"offset\": [" << r.offset[0] << ", " << r.offset[1] << "]}";
  }
  f << "\n]}\n";
}

// The scene as Unity saves it (YAML: m_LightmapIndex, m_LightmapTilingOffset per MeshRenderer).
void write_unity_scene(const std::string& path) {
  std::ofstream f(path);
  f << "%YAML 1.1\n%TAG !u! tag:unity3d.com,2011:\n";
  for (int k = 0; k < 4; ++k) {
    const Renderer& r = kRenderers[k];
    f << "--- !u!1 &" << 100 + k << "\nGameObject:\n  m_ObjectHideFlags: 0\n  m_Component:\n  - component: {fileID: " << 200 + k
      << "}\n  m_Layer: 0\n  m_Name: " << r.name << "\n";
    f << "--- !u!23 &" << 200 + k << "\nMeshRenderer:\n  m_GameObject: {fileID: " << 100 + k
      << "}\n  m_Enabled: 1\n  m_LightmapIndex: " << r.page << "\n  m_LightmapTilingOffset: {x: " << r.scale << ", y: " << r.scale
      << ", z: " << r.offset[0] << ", w: " << r.offset[1] << "}\n  m_LightmapIndexDynamic: 65535\n";
  }
}

// Page p's coverage by its renderers, placed by the library (what a baker lights).
std::vector<uint8_t> page_coverage(const std::string& gltf, const std::string& placement, int page) {
  const MeshInstances scene = read_mesh_instances(gltf, -1);
  const PlacedMesh pm = place_instances(scene, read_placements(placement), page, placement);
  return rasterise_lightmap_normals(pm.mesh, kPage, kPage).coverage;
}

// Unity's directional pair for page p: lit charts (the coverage and a one-texel ring, as Unity
// dilates), a flat fill elsewhere in both files.
void write_unity_page(const fs::path& dir, int page, const std::vector<uint8_t>& covered) {
  ImageF light(kPage, kPage, 3), dirs(kPage, kPage, 4);
  for (int y = 0; y < kPage; ++y)
    for (int x = 0; x < kPage; ++x) {
      bool lit = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          lit = lit || (xx >= 0 && yy >= 0 && xx < kPage && yy < kPage && covered[size_t(yy) * kPage + xx]);
        }
      float* l = light.at(x, y);
      float* d = dirs.at(x, y);
      if (lit) {
        l[0] = 0.2f + 0.6f * float(x) / kPage + 0.1f * float(page), l[1] = 0.3f + 0.5f * float(y) / kPage, l[2] = 0.45f;
        d[0] = 0.5f, d[1] = 220 / 255.f, d[2] = 0.5f, d[3] = 200 / 255.f;  // light from above, w < 1
      } else {  // Unity's flat fill of the unused atlas space
        l[0] = 0.0625f, l[1] = 0.0625f, l[2] = 0.0625f;
        d[0] = d[1] = d[2] = 128 / 255.f, d[3] = 1;
      }
    }
  const std::string base = (dir / ("Lightmap-" + std::to_string(page))).string();
  write_image(base + "_comp_light.exr", light, /*half=*/true);
  write_image(base + "_comp_dir.png", dirs);
}

// A Unity project's export: the editor script's glTF and placement, the scene YAML, both pages, a
// reflection probe beside them, and a wrong mesh (one quad, its UVs filling the square).
fs::path make_unity_project(const std::string& tag) {
  const fs::path d = ahd_test::temp_dir(tag);
  std::vector<std::pair<std::string, float>> nodes;
  for (int k = 0; k < 4; ++k) nodes.push_back({kRenderers[k].name, 2.0f * float(k)});
  write_quads_gltf((d / "Scene.ahdpack.gltf").string(), nodes);
  write_quads_gltf((d / "Full.gltf").string(), {{"Full", 0.0f}});
  write_placement_json((d / "Scene.ahdpack-placement.json").string());
  write_unity_scene((d / "Scene.unity").string());
  for (int p = 0; p < 2; ++p)
    write_unity_page(d, p, page_coverage((d / "Scene.ahdpack.gltf").string(), (d / "Scene.ahdpack-placement.json").string(), p));
  write_image((d / "ReflectionProbe-0.exr").string(), ImageF(8, 8, 3), true);
  return d;
}

// |got − want| relative to want (floored at 1e-6).
double rel_diff(float got, float want) { return std::fabs(double(got) - double(want)) / std::max(1e-6, std::fabs(double(want))); }

}  // namespace

TEST(BakerUnity, PageOneIsPlacedFromTheFileNameAndAWrongMeshIsRefusedOnTheFill) {
  const fs::path d = make_unity_project("unity_pages");
  // The README's recipe: page 1 from the file name, its two renderers placed.
  ahd_test::CliResult r = run_in(d, kUnityRecipe);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "layout auto: unity-directional")) << r.output;
  EXPECT_TRUE(contains(r.output, "placement: page 1 (Unity's file name Lightmap-1)")) << r.output;
  EXPECT_TRUE(contains(r.output, "2 instance(s) placed by Scene.ahdpack-placement.json")) << r.output;
  EXPECT_TRUE(contains(r.output, "atlas fill")) << r.output;  // the fill was found and set apart
  EXPECT_TRUE(fs::exists(d / "out" / "lightmap-1.json"));
  // The scene YAML places the same renderers: the same planes, byte for byte.
  r = run_in(d, "ahdpack convert Lightmap-1_comp_light.exr --mesh Scene.ahdpack.gltf --placement Scene.unity -o yaml/lightmap-1.ktx2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* plane : {"iz", "dir"}) {
    const std::string a = ahd_test::plane_file((d / "out" / "lightmap-1.json").string(), plane);
    const std::string b = ahd_test::plane_file((d / "yaml" / "lightmap-1.json").string(), plane);
    ASSERT_FALSE(a.empty()) << plane;
    EXPECT_EQ(read_file_bytes(a), read_file_bytes(b)) << plane;
  }
  // Page 0 reads its own renderers.
  r = run_in(d, "ahdpack convert Lightmap-0_comp_light.exr --mesh Scene.ahdpack.gltf --placement Scene.unity -o p0/lightmap-0.ktx2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "placement: page 0 (Unity's file name Lightmap-0)")) << r.output;
  // --page overrides the name: page 0's renderers on page 1's file lie on the fill, refused.
  r = run_in(d, "ahdpack convert Lightmap-1_comp_light.exr --mesh Scene.ahdpack.gltf --placement Scene.unity --page 0 -o bad/a.ktx2");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "ahdpack: error: Scene.ahdpack.gltf: UV set 1 does not match the lightmap")) << r.output;
  EXPECT_TRUE(contains(r.output, "on the atlas's fill")) << r.output;
  EXPECT_FALSE(fs::exists(d / "bad"));
  // A mesh whose lightmap UVs fill the square: every texel covered, the lit charts 28 % of them.
  r = run_in(d, "ahdpack convert Lightmap-1_comp_light.exr --mesh Full.gltf -o full/a.ktx2");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "ahdpack: error: Full.gltf: UV set 1 does not match the lightmap")) << r.output;
  EXPECT_TRUE(contains(r.output, "on the atlas's fill")) << r.output;
  EXPECT_FALSE(fs::exists(d / "full"));
  // Batch mode over the folder skips the reflection probe, saying so (the pages themselves need
  // their meshes: converted one by one above).
  r = run_in(d, "ahdpack convert . --layout plain -o batch/");
  EXPECT_TRUE(contains(r.output, "ReflectionProbe-0.exr skipped: a Unity reflection probe, not a lightmap")) << r.output;
  fs::remove_all(d);
}

TEST(BakerUnity, FillSetApartJudgesTheChartsNotTheBackground) {
  const fs::path d = make_unity_project("unity_fill");
  const std::string gltf = (d / "Scene.ahdpack.gltf").string(), placement = (d / "Scene.ahdpack-placement.json").string();
  // The page as read (unity-directional), judged against the right and the wrong coverage.
  ImageF light = read_image((d / "Lightmap-1_comp_light.exr").string());
  ShImage sh;
  sh.width = kPage, sh.height = kPage, sh.coeffs = 1;
  sh.data.assign(size_t(kPage) * kPage * 3, 0);
  sh.coverage.assign(sh.texels(), 1);
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int c = 0; c < 3; ++c) sh.data[i * 3 + size_t(c)] = light.data[i * 3 + size_t(c)];
  std::vector<uint8_t> fill;
  const size_t n_fill = fill_background(sh, &fill);
  const std::vector<uint8_t> right = page_coverage(gltf, placement, 1);
  size_t charts = 0;
  for (uint8_t c : right) charts += c;
  EXPECT_GT(charts, 0u);
  EXPECT_LT(n_fill, sh.texels() - charts);  // the ring around the charts is lit too
  EXPECT_GT(n_fill, sh.texels() / 2);       // 2 × 0.375² of the page is charts, the rest fill
  const CoverageComparison good = compare_coverage(right, sh);
  EXPECT_EQ(good.covered_fill, 0u);
  EXPECT_EQ(coverage_mismatch(good), "") << describe_coverage(good);
  const CoverageComparison wrong = compare_coverage(std::vector<uint8_t>(sh.texels(), 1), sh);
  EXPECT_EQ(wrong.covered_fill, n_fill);
  EXPECT_NE(coverage_mismatch(wrong), "") << describe_coverage(wrong);
  // One value throughout is no fill (nothing lit beside it).
  ShImage flat = sh;
  for (float& v : flat.data) v = 0.5f;
  EXPECT_EQ(fill_background(flat, &fill), 0u);
  fs::remove_all(d);
}

namespace {

// The Bevy sample's files copied into a fresh folder (the recipes write out/ beside them).
fs::path bevy_folder(const std::string& tag) {
  const fs::path d = ahd_test::temp_dir(tag);
  for (const char* f : {"CornellBox-Box.zstd.ktx2", "CornellBox-Large.zstd.ktx2", "CornellBox-Small.zstd.ktx2", "CornellBox.glb",
                        "cornell.jobs.json"})
    fs::copy_file(ahd_test::test_data(std::string("bevy/") + f), d / f);
  return d;
}

struct BevyObject {
  const char* file;
  const char* node;  // Bevy's GltfMeshName the sample matches
  const char* out;
};
const BevyObject kBevy[] = {{"CornellBox-Box.zstd.ktx2", "cornell_box", "box"},
                            {"CornellBox-Large.zstd.ktx2", "large_box", "large"},
                            {"CornellBox-Small.zstd.ktx2", "small_box", "small"}};

// Texels the node's triangles cover (its lightmap UVs, TEXCOORD_1).
std::vector<uint8_t> node_coverage(const std::string& glb, const std::string& node, int w, int h) {
  const MeshInstances scene = read_mesh_instances(glb, -1);
  std::vector<Placement> pl;
  for (const MeshInstance& i : scene.instances)
    for (const std::string& m : i.meshes)
      if (m == node || m.rfind(node + "-", 0) == 0) {
        pl.push_back({i.node, 0, {1, 1}, {0, 0}});
        break;
      }
  return rasterise_lightmap_normals(place_instances(scene, pl, 0, glb).mesh, w, h).coverage;
}

}  // namespace

TEST(BakerBevy, CornellBoxLightmapsConvertPerNodeAtTheInputScale) {
  AHD_REQUIRE_DATA(ahd_test::test_data("bevy/CornellBox.glb"));
  AHD_REQUIRE_DATA(ahd_test::test_data("bevy/CornellBox-Box.zstd.ktx2"));
  const fs::path d = bevy_folder("bevy_cornell");
  for (const BevyObject& o : kBevy) {
    const std::string cmd = std::string("ahdpack convert ") + o.file + " --mesh CornellBox.glb --node " + o.node + " -o out/" +
                            o.out + ".ktx2";
    if (std::string(o.out) == "large") {
      EXPECT_EQ(cmd, kBevyRecipe);
    }
    const ahd_test::CliResult r = run_in(d, cmd);
    ASSERT_EQ(r.exit_code, 0) << o.file << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, "layout auto: plain-ktx2")) << r.output;
    EXPECT_TRUE(contains(r.output, "iz scale: E/pi")) << r.output;
    EXPECT_FALSE(contains(r.output, "allow-mismatch")) << r.output;
    // The stored plane is the input, texel for texel on the object's charts, at its scale (no π).
    const std::string manifest = (d / "out" / (std::string(o.out) + ".json")).string();
    EXPECT_NEAR(read_manifest_file(manifest).iz_scale, 1 / M_PI, 1e-12);
    const ImageF in = read_image((d / o.file).string());
    const ImageF iz = read_image(ahd_test::plane_file(manifest, "iz"));
    ASSERT_EQ(iz.width, in.width);
    ASSERT_EQ(iz.height, in.height);
    const std::vector<uint8_t> cov = node_coverage((d / "CornellBox.glb").string(), o.node, in.width, in.height);
    size_t compared = 0;
    double worst = 0;
    for (size_t i = 0; i < in.texels(); ++i) {
      if (!cov[i]) continue;
      const float* a = &in.data[i * size_t(in.channels)];
      // Non-finite texels are zeroed on read and, like the baker's exact zeros (unlit), left to
      // the dilation: compared where the file holds light.
      if (!(std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]))) continue;
      if (a[0] == 0 && a[1] == 0 && a[2] == 0) continue;
      ++compared;
      for (int c = 0; c < 3; ++c) worst = std::max(worst, rel_diff(iz.data[i * size_t(iz.channels) + size_t(c)], a[c]));
    }
    EXPECT_GT(compared, in.texels() / 20) << o.file;
    // Half floats (the plane's RGBA16F) hold B10G11R11's values exactly; the read's E = π·x and
    // the stored E/π differ from x by float rounding only: at most half a half-float step.
    EXPECT_LE(worst, std::ldexp(1.0, -11)) << o.file << ": " << compared << " texels";
  }
  // The job file converts all three in one call (in a folder of its own), each output the single
  // conversion's bytes.
  const fs::path jobs = bevy_folder("bevy_jobs");
  const ahd_test::CliResult r = run_in(jobs, kBevyJobsRecipe);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const BevyObject& o : kBevy) {
    const std::string one = (d / "out" / (std::string(o.out) + ".json")).string();
    const std::string batch = (jobs / "out" / (std::string(o.out) + ".json")).string();
    ASSERT_TRUE(fs::exists(batch)) << r.output;
    EXPECT_EQ(read_file_bytes(ahd_test::plane_file(one, "iz")), read_file_bytes(ahd_test::plane_file(batch, "iz"))) << o.out;
  }
  // The wrong node's mesh is refused on the same lightmap.
  const ahd_test::CliResult wrong =
      run_in(d, "ahdpack convert CornellBox-Large.zstd.ktx2 --mesh CornellBox.glb --node small_box -o wrong/a.ktx2");
  EXPECT_EQ(wrong.exit_code, 1) << wrong.output;
  EXPECT_TRUE(contains(wrong.output, "does not match the lightmap")) << wrong.output;
  const ahd_test::CliResult missing =
      run_in(d, "ahdpack convert CornellBox-Large.zstd.ktx2 --mesh CornellBox.glb --node sofa -o wrong/a.ktx2");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_TRUE(contains(missing.output, "ahdpack: error: CornellBox.glb: no node or mesh named 'sofa' (nodes: ")) << missing.output;
  EXPECT_FALSE(fs::exists(d / "wrong"));
  fs::remove_all(d);
  fs::remove_all(jobs);
}

TEST(BakerPlain, LoneRgbExrConvertsAsPlainAtTheInputScale) {
  const fs::path d = ahd_test::temp_dir("plain_lone");
  ImageF img(32, 32, 3);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y)[c] = 0.1f + 0.02f * float(x) + 0.01f * float(y) + 0.05f * float(c);
  write_image((d / "lightmap.exr").string(), img, true);
  const ahd_test::CliResult r = run_in(d, kPlainRecipe);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "layout auto: plain")) << r.output;
  EXPECT_TRUE(contains(r.output, "because lightmap.exr: channels R, G, B only")) << r.output;
  const std::string manifest = (d / "out" / "lightmap.json").string();
  EXPECT_NEAR(read_manifest_file(manifest).iz_scale, 1 / M_PI, 1e-12);
  const ImageF in = read_image((d / "lightmap.exr").string());
  const ImageF iz = read_image(ahd_test::plane_file(manifest, "iz"));
  double worst = 0;
  for (size_t i = 0; i < in.texels(); ++i)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, rel_diff(iz.data[i * size_t(iz.channels) + size_t(c)], in.data[i * 3 + size_t(c)]));
  EXPECT_LE(worst, std::ldexp(1.0, -11));  // the input is half: the plane holds it (no factor π)
  // --iz-scale E still stores irradiance: π times the input.
  const ahd_test::CliResult e = run_in(d, "ahdpack convert lightmap.exr --iz-scale E -o e/lightmap.ktx2");
  ASSERT_EQ(e.exit_code, 0) << e.output;
  EXPECT_EQ(read_manifest_file((d / "e" / "lightmap.json").string()).iz_scale, 1.0);
  fs::remove_all(d);
}

TEST(BakerRecipes, ReadmeHoldsTheTestedCommands) {
  std::ifstream f(ahd_test::kSourceDir / ("READ" "ME.md"));  // (split: no doc citation for the checker)
  std::stringstream ss;
  ss << f.rdbuf();
  for (const char* recipe : {kUnityRecipe, kBevyRecipe, kBevyJobsRecipe, kPlainRecipe})
    EXPECT_TRUE(contains(ss.str(), std::string("`") + recipe + "`")) << "README.md lacks `" << recipe << "`";
}

// Godot from the files a Godot project has (issue 25): the real Godot 4.2 bake of
// tests/data/bakes/godot42-vermilion (scene, .lmbake, .glb meshes with UV0 only and their
// .glb.unwrap_cache) converts with no normals or placement file; the coverage rasterised from the
// meshes matches the lightmap's lit charts and the normals agree with the SH. The parsers refuse
// damaged bytes with one line. A mesh with the wrong UV set, or instances overlapping without
// placement, are refused naming the file and the remedy; --allow-mismatch still converts.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "file_bytes.h"
#include "godot_turned_bake.h"
#include "test_data.h"
#include "core/error.h"
#include "fit/fit_image.h"
#include "bakers/baker_layout.h"
#include "bakers/godot/godot_lmbake.h"
#include "bakers/godot/godot_scene.h"
#include "bakers/godot/godot_tscn.h"
#include "bakers/godot/godot_unwrap_cache.h"
#include "files/manifest_file.h"
#include "scene/placement_io.h"
#include "pipeline/plane_decode.h"
#include "scene/coverage_check.h"
#include "scene/lightmap_raster.h"

namespace fs = std::filesystem;
using namespace ahd;

namespace {

const fs::path kBake = ahd_test::test_data("bakes/godot42-vermilion");
const fs::path kScenes = kBake / "project" / "scenes";

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

std::vector<uint8_t> bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

#define NEED_BAKE() \
  if (!fs::exists(kScenes / "world.tscn")) GTEST_SKIP() << "no " << kScenes / "world.tscn"

// The rules the fit fires with the scene's normals, rotated about x by `degrees`.
FitStats fit_with_normals(double degrees, CoverageComparison* cc) {
  const ahd_test::TurnedBake b = ahd_test::read_turned_bake(kScenes, degrees);
  if (cc) *cc = compare_coverage(b.coverage, b.sh);
  FitStats st;
  fit_image(b.sh, FitOptions{}, 1, &st);
  return st;
}

}  // namespace

TEST(GodotScene, LmbakeUsersAreReadWithTheirRectangles) {
  NEED_BAKE();
  const GodotLightmapData d = read_godot_lmbake((kScenes / "world.lmbake").string());
  EXPECT_EQ(d.engine_major, 4);
  EXPECT_EQ(d.engine_minor, 2);
  EXPECT_TRUE(d.uses_spherical_harmonics);
  EXPECT_FALSE(d.has_packed_directional);
  ASSERT_EQ(d.users.size(), 55u);
  EXPECT_EQ(d.users[0].path, "../ApartmentA1Props/Windows/Window/Window");
  for (const GodotLightmapUser& u : d.users) {
    EXPECT_EQ(u.slice, 0) << u.path;
    EXPECT_EQ(u.sub_instance, -1) << u.path;
    EXPECT_GT(u.rect[2], 0) << u.path;
    EXPECT_LE(u.rect[0] + u.rect[2], 1.0 + 1e-6) << u.path;
    EXPECT_LE(u.rect[1] + u.rect[3], 1.0 + 1e-6) << u.path;
  }
}

TEST(GodotScene, DamagedBytesAreRefusedWithOneLine) {
  NEED_BAKE();
  std::vector<uint8_t> lm = bytes_of(kScenes / "world.lmbake");
  // Every truncation point either parses (never past the end) or throws ahd::Error.
  size_t refused = 0;
  for (size_t n = 0; n < lm.size(); n += 97) {
    try {
      parse_godot_lmbake(lm.data(), n, "x.lmbake");
    } catch (const Error& e) {
      ++refused;
      EXPECT_TRUE(contains(e.what(), "x.lmbake: ")) << e.what();
      EXPECT_FALSE(contains(e.what(), "\n"));
    }
  }
  EXPECT_GT(refused, lm.size() / 97 / 2);
  // A huge count is refused before allocation.
  std::vector<uint8_t> big = lm;
  big[0x6b] = 0xff, big[0x6c] = 0xff, big[0x6d] = 0xff, big[0x6e] = 0x7f;
  EXPECT_THROW(parse_godot_lmbake(big.data(), big.size(), "x"), Error);

  const std::vector<uint8_t> uc = bytes_of(kBake / "project/assets/models/apartments/window/window.glb.unwrap_cache");
  const auto entries = parse_godot_unwrap_cache(uc.data(), uc.size(), "w");
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].source_vertices, 145u);  // the glb's accessor count
  EXPECT_EQ(entries[0].indices.size(), 288u);
  for (size_t n = 0; n < uc.size(); n += 13) EXPECT_THROW(parse_godot_unwrap_cache(uc.data(), n, "w"), Error) << n;
  std::vector<uint8_t> bad = uc;
  bad[bad.size() - 4] = 0xff;  // the last index beyond the vertices
  EXPECT_THROW(parse_godot_unwrap_cache(bad.data(), bad.size(), "w"), Error);

  EXPECT_THROW(parse_godot_tscn("[node name=\"A\"]\ntransform = Transform3D(1, 2)\n", "t"), Error);
  const GodotTscn t = parse_godot_tscn(
      "[node name=\"A\" type=\"Node3D\"]\n[node name=\"B\" parent=\".\"]\n"
      "script/source = \"line one\n[node name=\\\"fake\\\"]\n\"\n"
      "transform = Transform3D(1, 0, 0, 0, 1, 0, 0, 0, 1, 4, 5, 6)\n",
      "t");
  ASSERT_EQ(t.nodes.size(), 2u);  // the header inside the multi-line string is not a node
  EXPECT_TRUE(t.nodes[1].has_transform);
  EXPECT_EQ(t.nodes[1].transform[10], 5);
}

// The Done-when: coverage against the lit charts, and the normals against the SH (rotated by 90°
// they contradict it: the horizon and negative-I_z rules fire far more often).
TEST(GodotScene, RealBakeCoverageMatchesTheLitChartsAndNormalsAgreeWithTheSh) {
  NEED_BAKE();
  CoverageComparison cc;
  const FitStats right = fit_with_normals(0, &cc);
  const FitStats rotated = fit_with_normals(90, nullptr);
  std::printf("coverage: %s\n", describe_coverage(cc).c_str());
  std::printf("rules: scene normals horizon-tilted %zu, negative I_z %zu; rotated 90 deg: %zu, %zu\n",
              right.dir_clamped, right.negative_iz, rotated.dir_clamped, rotated.negative_iz);
  EXPECT_GE(cc.iou, 0.95);
  EXPECT_EQ(coverage_mismatch(cc), "");
  EXPECT_GT(cc.covered, 140000u);
  EXPECT_LT(right.dir_clamped + right.negative_iz, (rotated.dir_clamped + rotated.negative_iz) / 5);
}

TEST(GodotScene, ConvertFindsTheSceneBesideTheExr) {
  NEED_BAKE();
  const fs::path dir = ahd_test::temp_dir("godot_scene_cli");
  const auto r = ahd_test::run_cli({"convert", (kScenes / "world.exr").string(), "-o", (dir / "w.ktx2").string(), "--levels", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "godot scene: ")) << r.output;
  EXPECT_TRUE(contains(r.output, "55 of 55 lightmap users placed")) << r.output;
  EXPECT_TRUE(fs::exists(dir / "w.json"));
  // The same with the scene named.
  const auto r2 = ahd_test::run_cli({"convert", (kScenes / "world.exr").string(), "--godot-scene",
                                     (kScenes / "world.tscn").string(), "-o", (dir / "w2.ktx2").string(), "--levels", "1"});
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  fs::remove_all(dir);
}

TEST(GodotScene, WrongUvSetIsRefusedNamingTheFileAndTheRemedyUnlessOverridden) {
  NEED_BAKE();
  const fs::path dir = ahd_test::temp_dir("godot_scene_wrong_uv");
  const std::string mesh = (kBake / "project/assets/models/apartments/apartment.glb").string();
  const auto r = ahd_test::run_cli({"convert", (kScenes / "world.exr").string(), "--mesh", mesh, "-o", (dir / "w.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "ahdpack: error: " + mesh + ": UV set 0 does not match the lightmap")) << r.output;
  EXPECT_TRUE(contains(r.output, "--godot-scene")) << r.output;
  EXPECT_TRUE(contains(r.output, "layout auto: godot4-unpacked")) << r.output;  // printed though the run fails
  EXPECT_FALSE(fs::exists(dir / "w.json"));
  const auto ok = ahd_test::run_cli({"convert", (kScenes / "world.exr").string(), "--mesh", mesh, "--allow-mismatch", "-o",
                                     (dir / "w.ktx2").string(), "--levels", "1"});
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  fs::remove_all(dir);
}

TEST(GodotScene, WorldSpaceWithoutNormalsNamesEveryWayToGiveThem) {
  NEED_BAKE();
  const fs::path dir = ahd_test::temp_dir("godot_scene_no_normals");
  for (const char* f : {"world.exr", "world.exr.import", "world.lmbake", "project.godot"})
    fs::copy_file(kBake / f, dir / f);
  const auto r = ahd_test::run_cli({"convert", (dir / "world.exr").string(), "-o", (dir / "w.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1);
  for (const char* way : {"--godot-scene", "--mesh", "--placement", "--normals"}) EXPECT_TRUE(contains(r.output, way)) << r.output;
  fs::remove_all(dir);
}

// Unity: a DOTS sub-scene's Lightmaps.unity has renderers but no m_LightmapIndex.
TEST(GodotScene, UnitySceneWithoutLightmapIndexSaysWhyAndWhatToGive) {
  const fs::path dir = ahd_test::temp_dir("unity_dots");
  const fs::path p = dir / "Lightmaps.unity";
  {
    std::ofstream f(p);
    f << "%YAML 1.1\n%TAG !u! tag:unity3d.com,2011:\n--- !u!1 &100\nGameObject:\n  m_Name: Wall\n"
         "--- !u!23 &200\nMeshRenderer:\n  m_GameObject: {fileID: 100}\n  m_Enabled: 1\n";
  }
  try {
    read_placements(p.string());
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, p.string() + ": 1 MeshRenderer(s) and none records m_LightmapIndex")) << m;
    EXPECT_TRUE(contains(m, "DOTS")) << m;
    EXPECT_TRUE(contains(m, "placement JSON")) << m;
  }
  fs::remove_all(dir);
}

// --iz-scale: the iz plane stores iz_scale × E, recorded in the manifest and the plane metadata;
// the direction and ratio do not change (the SH is linear in the light).
namespace {

// The editor's glTF export of the baked scene as Godot writes it (Scene > Export As > glTF 2.0): the
// node tree with the users' names, UV2 as TEXCOORD_1 (v down). Made here from the project's own
// files (load_godot_scene): one node per user along its path, identity transforms, world-space
// vertices. `prefix` is put before every name (a non-matching export).
void write_gltf_export(const GodotSceneMeshes& g, const fs::path& gltf, const std::string& prefix) {
  nlohmann::json j;
  j["asset"] = {{"version", "2.0"}};
  j["scene"] = 0;
  j["nodes"] = nlohmann::json::array({{{"name", prefix + "World"}, {"children", nlohmann::json::array()}}});
  j["meshes"] = j["accessors"] = j["bufferViews"] = nlohmann::json::array();
  std::vector<uint8_t> bin;
  std::map<std::string, int> node_of;
  const auto view = [&](const void* data, size_t bytes, int target) {
    const size_t at = bin.size();
    bin.insert(bin.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + bytes);
    while (bin.size() % 4) bin.push_back(0);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", bytes}, {"target", target}});
    return int(j["bufferViews"].size() - 1);
  };
  const auto accessor = [&](int bv, size_t count, int type, const char* kind) {
    j["accessors"].push_back({{"bufferView", bv}, {"componentType", type}, {"count", count}, {"type", kind}});
    return int(j["accessors"].size() - 1);
  };
  for (const MeshInstance& inst : g.scene.instances) {
    std::string path = inst.node;
    while (path.rfind("../", 0) == 0) path = path.substr(3);
    int parent = 0;
    std::string sofar;
    std::stringstream ss(path);
    for (std::string step; std::getline(ss, step, '/');) {
      sofar += "/" + step;
      auto it = node_of.find(sofar);
      if (it == node_of.end()) {
        j["nodes"].push_back({{"name", prefix + step}});
        it = node_of.emplace(sofar, int(j["nodes"].size() - 1)).first;
        j["nodes"][size_t(parent)]["children"].push_back(it->second);
      }
      parent = it->second;
    }
    const MeshTriangles& m = g.scene.mesh;
    std::vector<float> pos(m.positions.begin() + std::ptrdiff_t(inst.first_vertex * 3),
                           m.positions.begin() + std::ptrdiff_t((inst.first_vertex + inst.vertices) * 3));
    std::vector<float> nrm(m.normals.begin() + std::ptrdiff_t(inst.first_vertex * 3),
                           m.normals.begin() + std::ptrdiff_t((inst.first_vertex + inst.vertices) * 3));
    std::vector<float> uv;
    for (size_t v = inst.first_vertex; v < inst.first_vertex + inst.vertices; ++v)
      uv.insert(uv.end(), {m.uv[v * 2], 1.0f - m.uv[v * 2 + 1]});  // glTF: v down
    std::vector<uint32_t> idx;
    for (size_t k = inst.first_index; k < inst.first_index + inst.indices; ++k) idx.push_back(m.indices[k] - uint32_t(inst.first_vertex));
    const size_t n = inst.vertices;
    const int p = accessor(view(pos.data(), pos.size() * 4, 34962), n, 5126, "VEC3");
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (size_t v = 0; v < n; ++v)
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], pos[v * 3 + a]), hi[a] = std::max(hi[a], pos[v * 3 + a]);
    j["accessors"][size_t(p)]["min"] = {lo[0], lo[1], lo[2]};
    j["accessors"][size_t(p)]["max"] = {hi[0], hi[1], hi[2]};
    const int nr = accessor(view(nrm.data(), nrm.size() * 4, 34962), n, 5126, "VEC3");
    const int t = accessor(view(uv.data(), uv.size() * 4, 34962), n, 5126, "VEC2");
    const int ix = accessor(view(idx.data(), idx.size() * 4, 34963), idx.size(), 5125, "SCALAR");
    j["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", p}, {"NORMAL", nr}, {"TEXCOORD_0", t}, {"TEXCOORD_1", t}}},
                                             {"indices", ix}}}}});
    j["nodes"][size_t(parent)]["mesh"] = int(j["meshes"].size() - 1);
  }
  const fs::path bin_path = fs::path(gltf).replace_extension(".bin");
  j["buffers"] = {{{"uri", bin_path.filename().string()}, {"byteLength", bin.size()}}};
  j["scenes"] = {{{"nodes", {0}}}};
  std::ofstream(gltf) << j.dump();
  std::ofstream(bin_path, std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
}

}  // namespace

// Issue 25: a project without unwrap caches gives its scene as the editor's glTF export plus the
// .lmbake. The export's users are found by name and placed as the project's own files place them.
TEST(GodotScene, EditorGltfExportPlacedByTheLmbakeMatchesTheProject) {
  NEED_BAKE();
  const fs::path dir = ahd_test::temp_dir("godot_export");
  const GodotSceneMeshes project = load_godot_scene((kScenes / "world.tscn").string());
  write_gltf_export(project, dir / "world_export.gltf", "");
  const std::string lmbake = (kBake / "world.lmbake").string();
  const GodotSceneMeshes exported = load_godot_export((dir / "world_export.gltf").string(), lmbake);
  EXPECT_EQ(project.scene.instances.size(), 55u);
  ASSERT_EQ(exported.scene.instances.size(), project.scene.instances.size());
  ASSERT_EQ(exported.scene.mesh.positions.size(), project.scene.mesh.positions.size());
  double worst = 0;
  for (size_t k = 0; k < project.scene.mesh.positions.size(); ++k)
    worst = std::max(worst, double(std::abs(exported.scene.mesh.positions[k] - project.scene.mesh.positions[k])));
  for (size_t k = 0; k < project.scene.mesh.uv.size(); ++k)
    worst = std::max(worst, double(std::abs(exported.scene.mesh.uv[k] - project.scene.mesh.uv[k])));
  EXPECT_LT(worst, 1e-5);
  const RasterisedNormals a = rasterise_lightmap_normals(place_instances(project.scene, project.placements, 0, lmbake).mesh, 512, 512);
  const RasterisedNormals b = rasterise_lightmap_normals(place_instances(exported.scene, exported.placements, 0, lmbake).mesh, 512, 512);
  size_t differ = 0, covered = 0;
  for (size_t i = 0; i < a.coverage.size(); ++i) differ += a.coverage[i] != b.coverage[i], covered += a.coverage[i];
  EXPECT_LT(double(differ), 1e-3 * double(covered)) << differ << " of " << covered;

  // The command: --godot-scene takes the export, the .lmbake beside the EXR places it.
  fs::copy_file(kBake / "world.exr", dir / "world.exr");
  fs::copy_file(kBake / "world.exr.import", dir / "world.exr.import");
  fs::copy_file(kBake / "world.lmbake", dir / "world.lmbake");
  const auto r = ahd_test::run_cli({"convert", (dir / "world.exr").string(), "--godot-scene", (dir / "world_export.gltf").string(),
                                    "-o", (dir / "out/w.ktx2").string(), "--levels", "1"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "55 of 55 lightmap users placed by")) << r.output;

  // An export whose names are not the scene's: one line naming the file and what to do.
  write_gltf_export(project, dir / "renamed.gltf", "X");
  try {
    load_godot_export((dir / "renamed.gltf").string(), lmbake);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir / "renamed.gltf").string() + ": no node of the .lmbake's users", 0), 0u) << e.what();
  }
  fs::remove_all(dir);
}

// Issue 44: the export's .bin (its vertices and lightmap UVs) reached neither the key nor the
// depfile on the Godot route: a changed UV kept the key, so `--cache` published the old set.
TEST(GodotScene, GltfExportBufferIsInTheKeyAndTheDepfile) {
  NEED_BAKE();
  const fs::path dir = ahd_test::temp_dir("godot_export_bin");
  write_gltf_export(load_godot_scene((kScenes / "world.tscn").string()), dir / "world_export.gltf", "");
  for (const char* f : {"world.exr", "world.exr.import", "world.lmbake"}) fs::copy_file(kBake / f, dir / f);
  const auto run = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> a = {"convert", (dir / "world.exr").string(), "--godot-scene", (dir / "world_export.gltf").string(),
                                  "-o", (dir / "out/w.ktx2").string(), "--levels", "1", "-q"};
    a.insert(a.end(), extra.begin(), extra.end());
    return ahd_test::run_cli(a);
  };
  const auto k1 = run({"--print-key"});
  ASSERT_EQ(k1.exit_code, 0) << k1.output;
  ASSERT_EQ(run({"--depfile", (dir / "w.d").string()}).exit_code, 0);
  EXPECT_TRUE(contains(ahd_test::read_text(dir / "w.d"), fs::absolute(dir / "world_export.bin").lexically_normal().string()))
      << ahd_test::read_text(dir / "w.d");
  // The lowest mantissa bit of the first vertex's x changed: another key.
  std::string bin = ahd_test::read_text(dir / "world_export.bin");
  ASSERT_GT(bin.size(), 8u);
  bin[0] ^= 1;
  std::ofstream(dir / "world_export.bin", std::ios::binary | std::ios::trunc) << bin;
  const auto k2 = run({"--print-key"});
  ASSERT_EQ(k2.exit_code, 0) << k2.output;
  EXPECT_NE(k1.output, k2.output);
  fs::remove_all(dir);
}

TEST(IzScale, StoredScaleIsAppliedAndRecorded) {
  const fs::path dir = ahd_test::temp_dir("iz_scale");
  const auto run = [&](const std::vector<std::string>& extra, const std::string& out) {
    std::vector<std::string> args = {"convert", "--sample-size", "16", "--profile", "uncompressed", "--levels", "1", "-o",
                                     (dir / out / "s.ktx2").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return ahd_test::run_cli(args);
  };
  ASSERT_EQ(run({}, "e").exit_code, 0);
  ASSERT_EQ(run({"--iz-scale", "0.25"}, "q").exit_code, 0);
  const auto bad = run({"--iz-scale", "-1"}, "bad");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(contains(bad.output, "ahdpack: error: --iz-scale takes E, E/pi or a positive factor")) << bad.output;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  const auto decode = [&](const std::string& sub, Manifest* m) {
    const std::string path = (dir / sub / "s.json").string();
    *m = read_manifest_file(path);
    std::vector<Plane> planes;
    for (const auto& mp : m->planes) planes.push_back({mp.name, read_manifest_plane(path, mp)});
    for (const Plane& p : planes)
      if (p.name == "iz") {
        bool found = false;
        for (const auto& kv : p.texture.metadata) found = found || (kv.first == "ahd.iz_scale" && kv.second == (sub == "e" ? "1" : "0.25"));
        EXPECT_TRUE(found) << sub;
      }
    return decode_planes(planes, m->ratio_form == RatioForm::Rgb, 0);
  };
  Manifest me, mq;
  const DecodedPlanes e = decode("e", &me), q = decode("q", &mq);
  EXPECT_EQ(me.iz_scale, 1.0);
  EXPECT_EQ(mq.iz_scale, 0.25);
  ASSERT_EQ(e.iz.size(), q.iz.size());
  double worst = 0;
  for (size_t i = 0; i < e.iz.size(); ++i)
    worst = std::max(worst, std::fabs(double(q.iz[i]) - 0.25 * double(e.iz[i])) / std::max(1e-3, 0.25 * std::fabs(double(e.iz[i]))));
  EXPECT_LT(worst, 2e-3);  // half-float rounding of two different values
  fs::remove_all(dir);
}

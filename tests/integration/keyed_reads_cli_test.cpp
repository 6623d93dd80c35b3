// Issue 44, "read but not keyed" on every input route: what `strace -f -e trace=open,openat` sees
// the ahdpack process open for reading — regular files under the input's folders and the data
// folder (formats/) — must each be in the conversion's depfile, and the depfile must be the file list
// of the cache's inputs record (the list the key hashes: cook/conversion_key.h). A file read but not
// listed would change the output without changing the key (`--cache` serves an old set) or the
// depfile (no rebuild). Routes: a canonical EXR; a Bakery set by preset name and by a preset .json
// file; Godot projects (a scene with ArrayMesh resources and an instanced scene, one with .glb
// meshes); --mesh glTF with an external .bin; --mesh + --placement with a Unity scene; Bevy's KTX2
// with --node; a job file. Each route runs twice: the conversion, then the cache hit (which reads
// the recorded files only). Integration tests: they run the CLI (label `integration`).
// Skipped when strace is missing or not permitted (scripts/setup.sh installs it).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "file_bytes.h"
#include "layout_test_scene.h"
#include "depfile_deps.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

std::string norm(const fs::path& p) { return fs::absolute(p).lexically_normal().string(); }

bool under(const std::string& path, const fs::path& dir) { return path.rfind(norm(dir) + "/", 0) == 0; }

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

bool strace_works() { return ahd_test::run_shell("strace -f -qq -e trace=none true 2>&1; echo rc=$?") == "rc=0\n"; }

using ahd_test::depfile_deps;

// The "file" lines of every inputs record in the cache folder (paths as the command gave them,
// relative to `cwd`), absolute.
std::set<std::string> recorded_files(const fs::path& cache, const fs::path& cwd, size_t* records) {
  std::set<std::string> files;
  *records = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(cache, ec)) {
    if (e.path().extension() != ".ahdinputs") continue;
    ++*records;
    std::istringstream in(ahd_test::read_text(e.path()));
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("file ", 0) == 0) {
        const fs::path p = line.substr(5);
        files.insert(norm(p.is_absolute() ? p : cwd / p));
      }
  }
  return files;
}

struct Traced {
  std::string output;  // the command's stdout + stderr, then "rc=N"
  std::set<std::string> opened;  // regular files opened for reading under `roots`, absolute
};

// Runs ahdpack `args` in `cwd` under strace; keeps the files it opened read-only that lie under one
// of `roots` and under none of `skip` (the outputs, the cache) and are regular files.
Traced traced(const fs::path& cwd, const std::vector<std::string>& args, const std::vector<fs::path>& roots,
              const std::vector<fs::path>& skip, const fs::path& trace) {
  std::string cmd = "cd " + quoted(cwd.string()) +
                    " && ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\" strace -f -qq -e trace=open,openat -o " +
                    quoted(trace.string()) + " " + quoted(AHD_CLI_PATH);
  for (const std::string& a : args) cmd += " " + quoted(a);
  Traced t;
  t.output = ahd_test::run_shell(cmd + " 2>&1; echo rc=$?");
  std::istringstream lines(ahd_test::read_text(trace));
  std::string line;
  while (std::getline(lines, line)) {
    const size_t q = line.find('"'), e = q == std::string::npos ? q : line.find('"', q + 1);
    if (e == std::string::npos || line.find("O_WRONLY") != std::string::npos || line.find("O_RDWR") != std::string::npos ||
        line.find("O_DIRECTORY") != std::string::npos || line.find("= -1") != std::string::npos)
      continue;
    const fs::path p = line.substr(q + 1, e - q - 1);
    const std::string path = norm(p.is_absolute() ? p : cwd / p);
    bool keep = false;
    for (const fs::path& r : roots) keep = keep || under(path, r);
    for (const fs::path& s : skip) keep = keep && !under(path, s);
    if (keep && fs::is_regular_file(path)) t.opened.insert(path);
  }
  return t;
}

std::string listing(const std::set<std::string>& s) {
  std::string t;
  for (const std::string& x : s) t += "  " + x + "\n";
  return t;
}

const fs::path kFormats = fs::path(AHD_SOURCE_DIR) / "formats";

// One route: `args` (without -o/--depfile/--cache) converted in `dir` under strace, then again (a
// cache hit). Every file opened under `dir` or formats/ is in the depfile, the depfile is the inputs
// record's list, and every file of `must` is in it. Returns the depfile's list.
std::set<std::string> check_route(const fs::path& dir, std::vector<std::string> args, const std::vector<std::string>& must) {
  const fs::path out = dir / "out", cache = dir / "cache";
  args.insert(args.begin(), "convert");
  args.insert(args.end(), {"-o", (out / "r.ktx2").string(), "--depfile", (out / "r.d").string(), "--cache", cache.string(),
                           "--profile", "uncompressed", "--levels", "1", "-q"});
  const Traced first = traced(dir, args, {dir, kFormats}, {out, cache}, dir / "trace1.txt");
  EXPECT_NE(first.output.find("rc=0"), std::string::npos) << first.output;
  const std::set<std::string> deps = depfile_deps(out / "r.d");
  for (const std::string& f : first.opened) EXPECT_TRUE(deps.count(f)) << f << " was read but is not keyed; depfile:\n" << listing(deps);
  // The record holds the files actually read: each was opened (no stale or guessed name).
  for (const std::string& f : deps) EXPECT_TRUE(first.opened.count(f)) << f << " is keyed but was not read";
  size_t records = 0;
  EXPECT_EQ(recorded_files(cache, dir, &records), deps) << "depfile and the key's inputs record differ";
  EXPECT_EQ(records, 1u);
  for (const std::string& f : must) EXPECT_TRUE(deps.count(norm(dir / f))) << f << " missing from\n" << listing(deps);
  // The hit (the direct lookup: the recorded files hashed, no image decoded) reads nothing else.
  const Traced hit = traced(dir, args, {dir, kFormats}, {out, cache}, dir / "trace2.txt");
  EXPECT_NE(hit.output.find("rc=0"), std::string::npos) << hit.output;
  for (const std::string& f : hit.opened) EXPECT_TRUE(deps.count(f)) << f << " was read on the hit but is not keyed";
  EXPECT_EQ(depfile_deps(out / "r.d"), deps);
  return deps;
}

void spit(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// A quad (POSITION, NORMAL, TEXCOORD_0 over the whole map) in NAME.gltf with its buffer in NAME.bin,
// its node named `node`.
void write_quad_gltf(const fs::path& dir, const std::string& name, const std::string& node) {
  const float v[] = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1,  // positions
                     0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0,  // normals
                     0, 0, 1, 0, 1, 1, 0, 1};             // UVs
  const uint16_t idx[] = {0, 1, 2, 0, 2, 3};
  {
    std::ofstream b(dir / (name + ".bin"), std::ios::binary);
    b.write(reinterpret_cast<const char*>(v), sizeof v);
    b.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  spit(dir / (name + ".gltf"),
       R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"name":")" + node + R"(","mesh":0}],)"
       R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3}]}],)"
       R"("buffers":[{"uri":")" + name + R"(.bin","byteLength":140}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},)"
       R"({"buffer":0,"byteOffset":48,"byteLength":48},{"buffer":0,"byteOffset":96,"byteLength":32},)"
       R"({"buffer":0,"byteOffset":128,"byteLength":12}],"accessors":[{"bufferView":0,"componentType":5126,"count":4,)"
       R"("type":"VEC3","min":[0,0,0],"max":[1,0,1]},{"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},)"
       R"({"bufferView":2,"componentType":5126,"count":4,"type":"VEC2"},{"bufferView":3,"componentType":5123,"count":6,)"
       R"("type":"SCALAR"}]})");
}

// A Godot ≥ 4.4 set: World.exr (one packed page), World.exr.import, World.lmbake, project.godot.
void write_godot_set(const fs::path& d) {
  write_godot_packed(world_scene(), (d / "World.exr").string());
  spit(d / "World.exr.import", "[remap]\n\nimporter=\"2d_array_texture\"\ntype=\"CompressedTexture2DArray\"\n\n[params]\n\n"
                               "slices/horizontal=1\nslices/vertical=4\n");
  spit(d / "World.lmbake", std::string("RSRC\x01\x00\x00\x00", 8) + std::string("LightmapGIData\x00\x18_uses_packed_directional\x00", 41));
  spit(d / "project.godot", "config_version=5\n\n[application]\n\nconfig/features=PackedStringArray(\"4.6\", \"Forward Plus\")\n");
}

#define NEED_STRACE() \
  if (!strace_works()) GTEST_SKIP() << "strace is not available or not permitted here (scripts/setup.sh installs it)"

}  // namespace

TEST(KeyedReadsCli, CanonicalExr) {
  NEED_STRACE();
  const fs::path d = ahd_test::temp_dir("keyed_exr");
  ASSERT_EQ(ahd_test::run_cli({"sample", "--size", "16", "-o", (d / "s.exr").string()}).exit_code, 0);
  check_route(d, {"s.exr"}, {"s.exr"});
  fs::remove_all(d);
}

// Bakery's SH set (an .hdr and three .tga) by preset name, then by a preset given as a .json file
// beside it; the normal map is read too (a world-space layout).
TEST(KeyedReadsCli, BakerSetByPresetNameAndFile) {
  NEED_STRACE();
  const fs::path d = ahd_test::temp_dir("keyed_bakery");
  const WorldScene w = world_scene();
  write_bakery_sh(w, (d / "lm").string());
  write_image((d / "n.exr").string(), w.normals);
  const std::set<std::string> deps = check_route(d, {"lm", "--layout", "bakery-sh", "--normals", "n.exr"},
                                                 {"lm_L0.hdr", "lm_L1x.tga", "lm_L1y.tga", "lm_L1z.tga", "n.exr"});
  EXPECT_TRUE(deps.count(norm(kFormats / "bakers/bakery-sh.json"))) << listing(deps);
  const fs::path f = d / "file";
  fs::create_directories(f);
  for (const char* n : {"lm_L0.hdr", "lm_L1x.tga", "lm_L1y.tga", "lm_L1z.tga", "n.exr"}) fs::copy_file(d / n, f / n);
  fs::copy_file(kFormats / "bakers/bakery-sh.json", f / "my-preset.json");
  check_route(f, {"lm", "--layout", "my-preset.json", "--normals", "n.exr"}, {"my-preset.json", "lm_L0.hdr", "n.exr"});
  fs::remove_all(d);
}

// A Godot project found from the EXR: its .exr.import, .lmbake and project.godot; and the corpus
// projects whose scenes are read (ArrayMesh .res/.tres and an instanced .tscn; .glb meshes).
TEST(KeyedReadsCli, GodotProjects) {
  NEED_STRACE();
  const fs::path d = ahd_test::temp_dir("keyed_godot");
  write_godot_set(d);
  write_image((d / "n.exr").string(), world_scene().normals);
  check_route(d, {"World.exr", "--normals", "n.exr"}, {"World.exr", "World.exr.import", "World.lmbake", "project.godot", "n.exr"});
  for (const char* project : {"arraymeshes", "gltf"}) {
    const fs::path src = ahd_test::test_data(std::string("godot/corpus/") + project);
    if (!fs::exists(src / "project.godot")) continue;
    const fs::path p = d / project;
    fs::copy(src, p, fs::copy_options::recursive);
    const std::string exr = std::string(project) == "gltf" ? "world.exr" : "levels/level.exr";
    const std::string scene = std::string(project) == "gltf" ? "world.tscn" : "levels/level.tscn";
    const std::set<std::string> deps = check_route(p, {exr}, {exr, exr + ".import", "project.godot", scene});
    std::string meshes;
    for (const std::string& f : deps)
      if (f.size() > 4 && (f.compare(f.size() - 4, 4, ".glb") == 0 || f.compare(f.size() - 4, 4, ".res") == 0 ||
                           f.compare(f.size() - 5, 5, ".tres") == 0))
        meshes += f + "\n";
    EXPECT_FALSE(meshes.empty()) << project << ": no mesh file keyed\n" << listing(deps);
  }
  fs::remove_all(d);
}

// --mesh with a glTF whose buffer is an external .bin (read by the mesh reader, not by name).
TEST(KeyedReadsCli, MeshGltfWithBin) {
  NEED_STRACE();
  const fs::path d = ahd_test::temp_dir("keyed_mesh");
  write_godot_set(d);
  write_quad_gltf(d, "quad", "Quad");
  check_route(d, {"World.exr", "--mesh", "quad.gltf"}, {"World.exr", "quad.gltf", "quad.bin"});
  fs::remove_all(d);
}

// --mesh + --placement with Unity's scene YAML (CRLF line ends, as Windows editors save it).
TEST(KeyedReadsCli, MeshWithUnityScenePlacement) {
  NEED_STRACE();
  const fs::path d = ahd_test::temp_dir("keyed_unity");
  ImageF lm(16, 16, 3);
  for (size_t i = 0; i < lm.data.size(); ++i) lm.data[i] = 0.2f + 0.001f * float(i % 97);
  write_image((d / "Lightmap-0_comp_light.exr").string(), lm, true);
  write_quad_gltf(d, "scene", "Quad");
  spit(d / "Scene.unity",
       "%YAML 1.1\r\n%TAG !u! tag:unity3d.com,2011:\r\n--- !u!1 &100\r\nGameObject:\r\n  m_Name: Quad\r\n"
       "--- !u!23 &200\r\nMeshRenderer:\r\n  m_GameObject: {fileID: 100}\r\n  m_LightmapIndex: 0\r\n"
       "  m_LightmapTilingOffset: {x: 1, y: 1, z: 0, w: 0}\r\n");
  check_route(d, {"Lightmap-0_comp_light.exr", "--mesh", "scene.gltf", "--placement", "Scene.unity"},
              {"Lightmap-0_comp_light.exr", "scene.gltf", "scene.bin", "Scene.unity"});
  fs::remove_all(d);
}

// Bevy: a zstd-supercompressed KTX2 lightmap with --mesh GLB --node.
TEST(KeyedReadsCli, BevyKtx2WithNode) {
  NEED_STRACE();
  AHD_REQUIRE_DATA(ahd_test::test_data("bevy/CornellBox.glb"));
  AHD_REQUIRE_DATA(ahd_test::test_data("bevy/CornellBox-Small.zstd.ktx2"));
  const fs::path d = ahd_test::temp_dir("keyed_bevy");
  for (const char* f : {"CornellBox.glb", "CornellBox-Small.zstd.ktx2"}) fs::copy_file(ahd_test::test_data(std::string("bevy/") + f), d / f);
  check_route(d, {"CornellBox-Small.zstd.ktx2", "--mesh", "CornellBox.glb", "--node", "small_box"},
              {"CornellBox-Small.zstd.ktx2", "CornellBox.glb", norm(kFormats / "bakers/plain-ktx2.json")});
  fs::remove_all(d);
}

// A job file: --depfile describes one conversion, so each job's list is its inputs record in the
// cache. The job file itself is read by the command, not by a conversion: what it says that
// reaches the bytes (each job's options, output name and files) is in each job's key already.
TEST(KeyedReadsCli, JobFile) {
  NEED_STRACE();
  const fs::path d = ahd_test::temp_dir("keyed_jobs");
  write_godot_set(d);
  write_quad_gltf(d, "quad", "Quad");
  ASSERT_EQ(ahd_test::run_cli({"sample", "--size", "16", "-o", (d / "s.exr").string()}).exit_code, 0);
  spit(d / "level.jobs.json", R"({"jobs": [{"input": "World.exr", "mesh": "quad.gltf", "output": "world"},
                                           {"input": "s.exr", "output": "s"}]})");
  const fs::path out = d / "out", cache = d / "cache";
  const std::vector<std::string> args = {"convert", "--jobs", "level.jobs.json", "-o", out.string() + "/", "--cache",
                                         cache.string(), "--profile", "uncompressed", "--levels", "1", "-q"};
  const Traced first = traced(d, args, {d, kFormats}, {out, cache}, d / "trace1.txt");
  ASSERT_NE(first.output.find("rc=0"), std::string::npos) << first.output;
  size_t records = 0;
  const std::set<std::string> keyed = recorded_files(cache, d, &records);
  EXPECT_EQ(records, 2u);
  for (const char* f : {"World.exr", "World.exr.import", "World.lmbake", "project.godot", "quad.gltf", "quad.bin", "s.exr"})
    EXPECT_TRUE(keyed.count(norm(d / f))) << f << " missing from\n" << listing(keyed);
  for (const std::string& f : first.opened) {
    if (f != norm(d / "level.jobs.json")) EXPECT_TRUE(keyed.count(f)) << f << " was read but is not keyed:\n" << listing(keyed);
  }
  const Traced hit = traced(d, args, {d, kFormats}, {out, cache}, d / "trace2.txt");
  ASSERT_NE(hit.output.find("rc=0"), std::string::npos) << hit.output;
  for (const std::string& f : hit.opened) {
    if (f != norm(d / "level.jobs.json")) EXPECT_TRUE(keyed.count(f)) << f << " was read on the hit but is not keyed";
  }
  fs::remove_all(d);
}

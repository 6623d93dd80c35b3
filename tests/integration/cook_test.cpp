// The asset cook (issue 31): `convert --depfile` names every file a conversion read (checked against
// what the process really opened, by strace), `--print-key` covers every input byte and option,
// `--cache` reuses a conversion byte for byte and survives truncated entries and concurrent
// fillers, `verify` reads the baker's files as convert does, and a CMake + Ninja project cooks
// lightmaps incrementally through the installed ahdpack_add_lightmaps (tests/cook/run.sh).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "cli_runner.h"
#include "sanitized.h"
#include "containers/sha256.h"
#include "cook/conversion_cache.h"
#include "cook/depfile.h"
#include "layout_test_scene.h"
#include "depfile_deps.h"
#include "test_data.h"
#include "file_bytes.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;
using ahd_test::run_cli;

namespace {

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

void spit(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

std::string abs_path(const fs::path& p) { return fs::absolute(p).lexically_normal().string(); }

using ahd_test::depfile_deps;

// Every file of a folder (name -> bytes), for comparing two output sets.
std::map<std::string, std::string> folder_files(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) m[e.path().filename().string()] = ahd_test::read_text(e.path());
  return m;
}

// A Godot-style set in `dir`: World.exr with `pages` packed pages stacked (Godot ≥ 4.4: each page
// L0, L1y, L1z, L1x), World.exr.import, World.lmbake (a resource naming _uses_packed_directional),
// project.godot 4.6, and the normal map n.exr.
struct GodotSet {
  fs::path dir;
  std::string exr, normals;
  GodotSet(const fs::path& d, int pages, const std::string& stem = "World") : dir(d) {
    const WorldScene w = world_scene();
    exr = (d / (stem + ".exr")).string();
    normals = (d / "n.exr").string();
    write_image(normals, w.normals);
    const std::string one = (d / "one_page.exr").string();
    write_godot_packed(w, one);
    const ImageF page = read_image(one);
    fs::remove(one);
    ImageF atlas(page.width, page.height * pages, page.channels);
    for (int p = 0; p < pages; ++p)
      std::copy(page.data.begin(), page.data.end(), atlas.data.begin() + std::ptrdiff_t(p) * std::ptrdiff_t(page.data.size()));
    write_image(exr, atlas, /*half=*/true, {"R", "G", "B"});
    spit(exr + ".import", "[remap]\n\nimporter=\"2d_array_texture\"\ntype=\"CompressedTexture2DArray\"\n\n[params]\n\n"
                          "slices/horizontal=1\nslices/vertical=" + std::to_string(4 * pages) + "\n");
    spit(d / (stem + ".lmbake"), std::string("RSRC\x01\x00\x00\x00", 8) + std::string("LightmapGIData\x00\x18_uses_packed_directional\x00", 41));
    spit(d / "project.godot", "config_version=5\n\n[application]\n\nconfig/features=PackedStringArray(\"4.6\", \"Forward Plus\")\n");
  }
};

std::string key_of(const std::vector<std::string>& args) {
  std::vector<std::string> a = {"convert"};
  a.insert(a.end(), args.begin(), args.end());
  a.push_back("--print-key");
  const auto r = run_cli(a);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.size(), 65u) << r.output;  // 64 hex digits and a newline, nothing else
  return r.output.substr(0, 64);
}

}  // namespace

TEST(Cook, DepfileEscapesForMakeAndNinja) {
  EXPECT_EQ(depfile_text("out/a.json", {"/x y/c$d#e.exr", "/p/q.exr"}), "out/a.json: \\\n  /x\\ y/c$$d\\#e.exr \\\n  /p/q.exr\n");
  EXPECT_THROW(depfile_text("a.json", {"/bad\nname"}), Error);
}

// Issue 44: ';' (a command for Make), tab, '|', wildcards, quotes and backslash runs before a
// separator are refused, one error naming the path; ':' and '\' are escaped.
TEST(Cook, DepfileRefusesWhatMakeOrNinjaCannotCarry) {
  EXPECT_EQ(depfile_text("a.json", {"/x:y/p\\q.exr"}), "a.json: \\\n  /x\\:y/p\\q.exr\n");
  for (const std::string bad : {"/x;touch\tPWNED;true.exr", "/a;b", "/a\tb", "/a|b", "/a*b", "/a?b", "/a[b]", "/a%b",
                                "/a=b", "/a'b", "/a\"b", "/a\\ b", "/a\\#b", "/a\\\\b", "/a\\", "/a(b)", "/a\rb"}) {
    try {
      depfile_text("a.json", {bad});
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      // Control characters are printed escaped (file_error's printable_path): the cause is checked.
      EXPECT_TRUE(contains(e.what(), ": cannot be written to a depfile: ")) << e.what();
    }
  }
  EXPECT_THROW(depfile_text("~a.json", {"/p"}), Error);
}

// Issue 44, with the real tools: an input under a folder named "we ird#$x:y\z" gets a depfile that
// GNU Make and Ninja both read as that one path (a newer input rebuilds, an unchanged one does not);
// an input under "x;touch<TAB>PWNED;true" is refused (exit 1, one line, no output at all), so no
// build tool ever sees it.
TEST(Cook, DepfileRebuildsWithMakeAndNinja) {
  const bool have_make = ahd_test::run_shell("command -v make >/dev/null && echo yes") == "yes\n";
  const bool have_ninja = ahd_test::run_shell("command -v ninja >/dev/null && echo yes") == "yes\n";
  if (!have_make || !have_ninja) GTEST_SKIP() << "needs GNU make and ninja on PATH";
  const fs::path d = fs::absolute(ahd_test::temp_dir("cook_depfile_tools"));
  const fs::path weird = d / "we ird#$x:y\\z";
  fs::create_directories(weird);
  const std::string in = (weird / "s.exr").string();
  ASSERT_EQ(run_cli({"sample", "--size", "16", "-o", in}).exit_code, 0);
  const auto r = run_cli({"convert", in, "-o", (d / "out" / "s.ktx2").string(), "--profile", "uncompressed", "-q",
                          "--depfile", (d / "out" / "s.d").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Make: the rule's only prerequisites come from the depfile (whose target is -o's manifest path,
  // absolute here).
  const std::string target = (d / "out" / "s.json").string();
  spit(d / "Makefile", target + ":\n\t@echo REBUILD\n-include out/s.d\n");
  const auto make_q = [&] { return ahd_test::run_shell("cd '" + d.string() + "' && make -q '" + target + "' 2>&1; echo rc=$?"); };
  const std::string db = ahd_test::run_shell("cd '" + d.string() + "' && make -p -q '" + target + "' 2>/dev/null");
  EXPECT_TRUE(contains(db, "\n" + target + ": " + in + " ")) << ahd_test::read_text(d / "out" / "s.d");  // then the profile
  EXPECT_TRUE(contains(make_q(), "rc=0")) << make_q();
  // Ninja: the depfile read after the build (deps = gcc, which deletes it: a copy), its one
  // dependency listed as is.
  fs::copy_file(d / "out" / "s.d", d / "ninja.d");
  spit(d / "build.ninja", "rule cook\n  command = true\n  depfile = ninja.d\n  deps = gcc\nbuild " + target + ": cook\n");
  const std::string ninja = "cd '" + d.string() + "' && ninja ";
  ahd_test::run_shell(ninja + ">/dev/null 2>&1");
  const std::string deps = ahd_test::run_shell(ninja + "-t deps '" + target + "'");
  EXPECT_TRUE(contains(deps, "\n    " + in + "\n")) << deps;
  EXPECT_TRUE(contains(ahd_test::run_shell(ninja + "-n 2>&1"), "no work to do"));
  fs::last_write_time(in, fs::last_write_time(in) + std::chrono::hours(1));
  EXPECT_TRUE(contains(make_q(), "rc=1")) << make_q();
  EXPECT_FALSE(contains(ahd_test::run_shell(ninja + "-n 2>&1"), "no work to do"));

  // The attack: refused before anything is written; make never sees a recipe.
  const fs::path pwn = d / "x;touch\tPWNED;true";
  fs::create_directories(pwn);
  const std::string pin = (pwn / "s.exr").string();
  fs::copy_file(in, pin);
  const auto bad = run_cli({"convert", pin, "-o", (d / "pwn" / "s.ktx2").string(), "--profile", "uncompressed", "-q",
                            "--depfile", (d / "pwn" / "s.d").string()});
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_EQ(bad.output.rfind("ahdpack: error: " + d.string() + "/x;touch\\tPWNED;true/s.exr: cannot be written to a depfile: the character ';'", 0), 0u) << bad.output;
  EXPECT_EQ(std::count(bad.output.begin(), bad.output.end(), '\n'), 1) << bad.output;
  EXPECT_FALSE(fs::exists(d / "pwn"));
  EXPECT_FALSE(fs::exists(d / "PWNED"));
  fs::remove_all(d);
}

// The done-when of issue 31: a Godot multi-page conversion's depfile names the .exr.import, the
// .lmbake and every image — and, checked by strace, every file the process opened for reading
// among the inputs' folder and the data files.
TEST(Cook, GodotAtlasDepfileNamesEveryFileRead) {
  const fs::path d = ahd_test::temp_dir("cook_depfile");
  const GodotSet g(d, 4);
  const fs::path out = d / "out";
  const auto r = run_cli({"convert", g.exr, "--normals", g.normals, "-o", (out / "atlas.ktx2").string(), "--depfile",
                          (out / "atlas.d").string(), "--profile", "pc-bc"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(contains(r.output, "4 page(s) from World.exr.import")) << r.output;
  ASSERT_TRUE(contains(r.output, "World.lmbake: has _uses_packed_directional")) << r.output;
  EXPECT_EQ(ahd_test::read_text(out / "atlas.d").rfind((out / "atlas.json").string() + ":", 0), 0u) << ahd_test::read_text(out / "atlas.d");
  const std::set<std::string> deps = depfile_deps(out / "atlas.d");
  for (const std::string f : {g.exr, g.exr + ".import", (d / "World.lmbake").string(), (d / "project.godot").string(), g.normals})
    EXPECT_TRUE(deps.count(abs_path(f))) << f << " missing from\n" << ahd_test::read_text(out / "atlas.d");
  const std::string formats = abs_path(fs::path(AHD_SOURCE_DIR) / "formats");
  EXPECT_TRUE(deps.count(formats + "/profiles/pc-bc.json")) << ahd_test::read_text(out / "atlas.d");
  EXPECT_TRUE(deps.count(formats + "/bakers/godot4-packed.json")) << ahd_test::read_text(out / "atlas.d");
  for (const std::string& dep : deps) EXPECT_TRUE(fs::is_regular_file(dep)) << dep;

  // What the process opened for reading: each such file among the inputs and data files is named.
  if (ahd_test::run_shell("strace -f -qq -e trace=none true 2>&1; echo rc=$?") != "rc=0\n")
    GTEST_SKIP() << "strace is not available or not permitted here";
  const fs::path trace = d / "trace.txt";
  // LeakSanitizer cannot run under ptrace: a sanitizer build's ahdpack runs without it here.
  const std::string cmd = "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\" strace -f -qq -e trace=open,openat -o '" + trace.string() + "' '" + AHD_CLI_PATH + "' convert '" +
                          g.exr + "' --normals '" + g.normals + "' -o '" + (d / "out2" / "atlas.ktx2").string() +
                          "' --profile pc-bc -q --depfile '" + (d / "out2" / "atlas.d").string() + "' 2>&1; echo rc=$?";
  ASSERT_EQ(ahd_test::run_shell(cmd), "rc=0\n");
  std::istringstream lines(ahd_test::read_text(trace));
  std::string line;
  size_t checked = 0;
  while (std::getline(lines, line)) {
    const size_t q = line.find('"'), e = q == std::string::npos ? q : line.find('"', q + 1);
    if (e == std::string::npos || contains(line, "O_WRONLY") || contains(line, "O_RDWR") || contains(line, "O_DIRECTORY") ||
        contains(line, "= -1"))
      continue;
    const std::string path = abs_path(line.substr(q + 1, e - q - 1));
    const bool input_side = path.rfind(abs_path(d) + "/", 0) == 0 && path.rfind(abs_path(d / "out2") + "/", 0) != 0;
    if (!input_side && path.rfind(formats + "/", 0) != 0) continue;  // libraries, /proc, …
    if (!fs::is_regular_file(path)) continue;
    ++checked;
    EXPECT_TRUE(deps.count(path)) << path << " was read but is not in the depfile";
  }
  EXPECT_GE(checked, 7u) << ahd_test::read_text(trace);  // the 5 Godot files and the 2 data files at least
  EXPECT_EQ(ahd_test::read_text(out / "atlas.d").substr(ahd_test::read_text(out / "atlas.d").find(':')),
            ahd_test::read_text(d / "out2" / "atlas.d").substr(ahd_test::read_text(d / "out2" / "atlas.d").find(':')));
  fs::remove_all(d);
}

// A mesh's external buffer is read by Assimp, not by us: the recording IOSystem notes it too.
TEST(Cook, DepfileNamesAMeshAndItsBuffers) {
  const fs::path d = ahd_test::temp_dir("cook_mesh");
  const GodotSet g(d, 1);
  const float v[] = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1,  // positions
                     0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0,  // normals
                     0, 0, 1, 0, 1, 1, 0, 1};             // lightmap UVs over the whole atlas
  const uint16_t idx[] = {0, 1, 2, 0, 2, 3};
  {
    std::ofstream b(d / "quad.bin", std::ios::binary);
    b.write(reinterpret_cast<const char*>(v), sizeof v);
    b.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  spit(d / "quad.gltf",
       R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
       R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3}]}],)"
       R"("buffers":[{"uri":"quad.bin","byteLength":140}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},)"
       R"({"buffer":0,"byteOffset":48,"byteLength":48},{"buffer":0,"byteOffset":96,"byteLength":32},)"
       R"({"buffer":0,"byteOffset":128,"byteLength":12}],"accessors":[{"bufferView":0,"componentType":5126,"count":4,)"
       R"("type":"VEC3","min":[0,0,0],"max":[1,0,1]},{"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},)"
       R"({"bufferView":2,"componentType":5126,"count":4,"type":"VEC2"},{"bufferView":3,"componentType":5123,"count":6,)"
       R"("type":"SCALAR"}]})");
  const auto r = run_cli({"convert", g.exr, "--mesh", (d / "quad.gltf").string(), "-o", (d / "o" / "w.ktx2").string(),
                          "--depfile", (d / "o" / "w.d").string(), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::set<std::string> deps = depfile_deps(d / "o" / "w.d");
  EXPECT_TRUE(deps.count(abs_path(d / "quad.gltf"))) << ahd_test::read_text(d / "o" / "w.d");
  EXPECT_TRUE(deps.count(abs_path(d / "quad.bin"))) << ahd_test::read_text(d / "o" / "w.d");
  EXPECT_FALSE(deps.count(abs_path(g.normals))) << ahd_test::read_text(d / "o" / "w.d");  // not read: the mesh gives the normals
  fs::remove_all(d);
}

TEST(Cook, KeyCoversEveryInputByteAndOption) {
  const fs::path d = ahd_test::temp_dir("cook_key");
  const std::string in = (d / "s.exr").string(), out = (d / "o" / "s.ktx2").string();
  ASSERT_EQ(run_cli({"sample", "--size", "32", "-o", in}).exit_code, 0);
  const std::string base = key_of({in, "-o", out, "--profile", "pc-bc"});
  // Not in the key: thread count, verbosity, the output's folder, the input's path.
  EXPECT_EQ(key_of({in, "-o", out, "--profile", "pc-bc", "--threads", "1", "-q"}), base);
  EXPECT_EQ(key_of({in, "-o", (d / "elsewhere" / "s.ktx2").string(), "--profile", "pc-bc"}), base);
  fs::copy_file(in, d / "copy.exr");
  EXPECT_EQ(key_of({(d / "copy.exr").string(), "-o", out, "--profile", "pc-bc"}), base);
  // In the key: every option that reaches the bytes, and the output's name and container.
  std::set<std::string> keys = {base};
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--zstd"}, {"--eps", "0.06"}, {"--quality", "fast"}, {"--levels", "2"}, {"--direction", "keep"},
        {"--strict-ktx"}, {"--measure", "full"}, {"--open-loop"}, {"--coverage-plane"},
        {"--direction-fit", "linear"}, {"--ambient-threshold", "0.02"}}) {
    std::vector<std::string> args = {in, "-o", out, "--profile", "pc-bc"};
    args.insert(args.end(), extra.begin(), extra.end());
    EXPECT_TRUE(keys.insert(key_of(args)).second) << extra[0] << " does not change the key";
  }
  EXPECT_TRUE(keys.insert(key_of({in, "-o", out, "--profile", "uncompressed"})).second);
  EXPECT_TRUE(keys.insert(key_of({in, "-o", out, "--profile", "uncompressed-rgb"})).second);
  EXPECT_TRUE(keys.insert(key_of({in, "-o", out, "--profile", "uncompressed-rgb", "--ratio", "luminance"})).second);
  EXPECT_TRUE(keys.insert(key_of({in, "-o", (d / "o" / "t.ktx2").string(), "--profile", "pc-bc"})).second);
  EXPECT_TRUE(keys.insert(key_of({in, "-o", (d / "o" / "s.dds").string(), "--profile", "pc-bc"})).second);
  // A profile file one byte longer (same meaning) is another input.
  const fs::path prof = d / "mine.json";
  spit(prof, ahd_test::read_text(fs::path(AHD_SOURCE_DIR) / "formats" / "profiles" / "pc-bc.json"));
  const std::string k_file = key_of({in, "-o", out, "--profile", prof.string()});
  spit(prof, ahd_test::read_text(prof) + " ");
  EXPECT_NE(key_of({in, "-o", out, "--profile", prof.string()}), k_file);
  // Another scene in the input file.
  ASSERT_EQ(run_cli({"sample", "--size", "32", "--seed", "3", "-o", in}).exit_code, 0);
  EXPECT_TRUE(keys.insert(key_of({in, "-o", out, "--profile", "pc-bc"})).second);
  // A Godot set: one byte of a comment in the .exr.import (same conversion) changes the key, as
  // does the .lmbake.
  const GodotSet g(d / "godot", 1);
  const std::vector<std::string> gargs = {g.exr, "--normals", g.normals, "-o", out};
  const std::string kg = key_of(gargs);
  spit(g.exr + ".import", ahd_test::read_text(g.exr + ".import") + "; a comment\n");
  const std::string kg2 = key_of(gargs);
  EXPECT_NE(kg2, kg);
  spit(g.dir / "World.lmbake", ahd_test::read_text(g.dir / "World.lmbake") + "x");
  EXPECT_NE(key_of(gargs), kg2);
  fs::remove_all(d);
}

TEST(Cook, CacheHitWritesTheBytesOfTheConversion) {
  const fs::path d = ahd_test::temp_dir("cook_cache");
  const std::string in = (d / "s.exr").string(), cache = (d / "cache").string();
  ASSERT_EQ(run_cli({"sample", "--size", "32", "-o", in}).exit_code, 0);
  const auto conv = [&](const std::string& dir, std::vector<std::string> extra = {}) {
    std::vector<std::string> a = {"convert", in, "-o", (d / dir / "s.ktx2").string(), "--profile", "pc-bc", "--cache", cache,
                                  "--depfile", (d / dir / "s.d").string()};
    a.insert(a.end(), extra.begin(), extra.end());
    return run_cli(a);
  };
  auto r = conv("miss");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "cache: stored")) << r.output;
  r = conv("hit");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "cache hit")) << r.output;
  const auto miss_files = folder_files(d / "miss"), hit_files = folder_files(d / "hit");
  ASSERT_EQ(miss_files.size(), 6u);  // 3 planes, manifest, report, depfile
  for (const auto& [name, bytes] : miss_files) {
    if (name == "s.d") continue;  // names its own target path
    ASSERT_TRUE(hit_files.count(name)) << name;
    EXPECT_EQ(hit_files.at(name), bytes) << name;
  }
  EXPECT_EQ(depfile_deps(d / "hit" / "s.d"), depfile_deps(d / "miss" / "s.d"));
  // A direct conversion (no cache) writes the same planes and manifest.
  ASSERT_EQ(run_cli({"convert", in, "-o", (d / "direct" / "s.ktx2").string(), "--profile", "pc-bc", "-q"}).exit_code, 0);
  for (const auto& [name, bytes] : folder_files(d / "direct"))
    if (name != "s.report.json") EXPECT_EQ(hit_files.at(name), bytes) << name;
  // Another option misses (and is stored beside); the first entry still hits.
  r = conv("zstd", {"--zstd"});
  EXPECT_TRUE(contains(r.output, "cache: stored")) << r.output;
  r = conv("hit2");
  EXPECT_TRUE(contains(r.output, "cache hit")) << r.output;
  // Another input byte misses.
  ASSERT_EQ(run_cli({"sample", "--size", "32", "--seed", "5", "-o", in}).exit_code, 0);
  r = conv("seed5");
  EXPECT_TRUE(contains(r.output, "cache: stored")) << r.output;
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(cache)) entries += e.path().extension() == ".ahdcache";
  EXPECT_EQ(entries, 3u);
  fs::remove_all(d);
}

TEST(Cook, TruncatedOrCorruptCacheEntryIsIgnoredAndReplaced) {
  const fs::path d = ahd_test::temp_dir("cook_corrupt");
  const std::string in = (d / "s.exr").string(), cache = (d / "cache").string();
  ASSERT_EQ(run_cli({"sample", "--size", "32", "-o", in}).exit_code, 0);
  const std::vector<std::string> args = {"convert", in, "-o", (d / "o" / "s.ktx2").string(), "--cache", cache};
  ASSERT_EQ(run_cli(args).exit_code, 0);
  fs::path entry;
  for (const auto& e : fs::directory_iterator(cache))
    if (e.path().extension() == ".ahdcache") entry = e.path();
  const std::string good = ahd_test::read_text(entry);
  const std::string key = entry.stem().string();
  ASSERT_TRUE(ConversionCache::decode(key, std::vector<uint8_t>(good.begin(), good.end())));
  const auto expected = folder_files(d / "o");
  const std::vector<std::string> damage = {good.substr(0, good.size() - 100), good.substr(0, good.size() / 3),
                                           good.substr(0, good.size() - 1) + char(good.back() ^ 1), good + "x", "garbage"};
  for (size_t i = 0; i < damage.size(); ++i) {
    spit(entry, damage[i]);
    fs::remove_all(d / "o");
    const auto r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "cache: stored")) << "damage " << i << ": " << r.output;  // a miss, converted again
    const std::string now = ahd_test::read_text(entry);  // replaced by a whole entry (the report's seconds may differ)
    EXPECT_TRUE(ConversionCache::decode(key, std::vector<uint8_t>(now.begin(), now.end()))) << i;
    for (const auto& [name, bytes] : folder_files(d / "o"))
      if (name != "s.report.json") EXPECT_EQ(bytes, expected.at(name)) << name;
  }
  fs::remove_all(d);
}

// Issue 44: a hit published the entry's manifest without checking it against the stored planes. An
// entry that is well-formed (every header hash right) but whose plane is not the one its manifest
// records, or that carries a file no manifest names: a warning and a miss, never published.
TEST(Cook, CacheEntryNotMatchingItsManifestIsAMiss) {
  const fs::path d = ahd_test::temp_dir("cook_mismatch");
  const std::string in = (d / "s.exr").string(), cache = (d / "cache").string();
  ASSERT_EQ(run_cli({"sample", "--size", "32", "-o", in}).exit_code, 0);
  const std::vector<std::string> args = {"convert", in, "-o", (d / "o" / "s.ktx2").string(), "--cache", cache,
                                         "--profile", "uncompressed"};
  ASSERT_EQ(run_cli(args).exit_code, 0);
  fs::path entry;
  for (const auto& e : fs::directory_iterator(cache))
    if (e.path().extension() == ".ahdcache") entry = e.path();
  const std::string key = entry.stem().string(), good = ahd_test::read_text(entry);
  const auto expected = folder_files(d / "o");
  const std::vector<OutputFile> files = *ConversionCache::decode(key, std::vector<uint8_t>(good.begin(), good.end()));
  std::vector<std::vector<OutputFile>> broken;
  for (size_t i = 0; i < files.size(); ++i)
    if (files[i].name.find(".iz.") != std::string::npos) {
      broken.push_back(files);
      broken.back()[i].bytes.back() ^= 1;  // same size, another SHA-256
      broken.push_back(files);
      broken.back()[i].bytes.pop_back();  // another size
      broken.push_back(files);
      broken.back().erase(broken.back().begin() + std::ptrdiff_t(i));  // missing
    }
  broken.push_back(files);
  broken.back().push_back({"s.extra.ktx2", {1, 2, 3}});  // a file no manifest names
  ASSERT_EQ(broken.size(), 4u);
  for (size_t i = 0; i < broken.size(); ++i) {
    spit(entry, std::string([&] {
           const std::vector<uint8_t> b = ConversionCache::encode(key, broken[i]);
           return std::string(b.begin(), b.end());
         }()));
    fs::remove_all(d / "o");
    const auto r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, entry.string() + ": cache entry refused (")) << i << ": " << r.output;
    EXPECT_TRUE(contains(r.output, "cache: stored")) << i << ": " << r.output;  // converted again
    EXPECT_FALSE(contains(r.output, "cache hit")) << i << ": " << r.output;
    for (const auto& [name, bytes] : folder_files(d / "o"))
      if (name != "s.report.json") EXPECT_EQ(bytes, expected.at(name)) << name;
  }
  fs::remove_all(d);
}

// Issue 44: a lookup read a whole entry into memory (an 8 GB sparse entry: out of memory on every
// run), and a stored inputs record could make the key hash /dev/zero or block on a FIFO. Under a
// 4 GB address limit and a 120 s timeout: the sparse entry is a miss without reading it, the
// record naming /dev/zero or a FIFO falls back to reading the input (a normal hit).
TEST(Cook, CacheNeverReadsHugeEntriesOrSpecialFiles) {
  const fs::path d = ahd_test::temp_dir("cook_special");
  const std::string in = (d / "s.exr").string(), cache = (d / "cache").string();
  ASSERT_EQ(run_cli({"sample", "--size", "16", "-o", in}).exit_code, 0);
  // Sanitizer builds reserve terabytes of shadow memory: no address limit there, the timeout stays.
  const std::string limit = ahd_test::kSanitized ? "" : "ulimit -v 4000000; ";
  const std::string cmd = limit + "timeout 120 '" + std::string(AHD_CLI_PATH) + "' convert '" + in + "' -o '" +
                          (d / "o" / "s.ktx2").string() + "' --profile uncompressed --cache '" + cache + "' 2>&1; echo rc=$?";
  std::string out = ahd_test::run_shell(cmd);
  ASSERT_TRUE(contains(out, "rc=0")) << out;
  fs::path entry, inputs;
  for (const auto& e : fs::directory_iterator(cache)) {
    if (e.path().extension() == ".ahdcache") entry = e.path();
    if (e.path().extension() == ".ahdinputs") inputs = e.path();
  }
  ASSERT_FALSE(entry.empty());
  ASSERT_FALSE(inputs.empty());
  // An 8 GB sparse file in the entry's place.
  fs::remove(entry);
  { std::ofstream(entry) << "ahdpack-cache 1\n"; }
  fs::resize_file(entry, uint64_t(8) << 30);
  out = ahd_test::run_shell(cmd);
  EXPECT_TRUE(contains(out, "rc=0")) << out;
  EXPECT_TRUE(contains(out, "cache: stored")) << out;  // a miss, converted and stored again
  EXPECT_LT(fs::file_size(entry), uint64_t(1) << 30);
  // The inputs record's file line pointed at /dev/zero, then at a FIFO (its own SHA-256 redone).
  const std::string record = ahd_test::read_text(inputs);
  ASSERT_TRUE(contains(record, "\nfile " + in + "\n")) << record;
  ASSERT_EQ(::mkfifo((d / "fifo").c_str(), 0600), 0);
  for (const std::string& special : {std::string("/dev/zero"), (d / "fifo").string()}) {
    std::string t = record.substr(0, record.rfind("sha256 "));
    t.replace(t.find("\nfile " + in + "\n"), in.size() + 7, "\nfile " + special + "\n");
    t += "sha256 " + sha256_hex(reinterpret_cast<const uint8_t*>(t.data()), t.size()) + "\n";
    spit(inputs, t);
    out = ahd_test::run_shell(cmd);
    EXPECT_TRUE(contains(out, "rc=0")) << special << ": " << out;
    EXPECT_TRUE(contains(out, "cache hit")) << special << ": " << out;  // read again, the key's entry found
  }
  fs::remove_all(d);
}

// The second run of a command finds its conversion without reading the images (the direct lookup
// of cook/conversion_cache.h) — unless a file it found absent has appeared: a .lmbake that now says
// how the L1 is stored must be read, so the run reads again and misses.
TEST(Cook, CacheDirectLookupRereadsWhenAProbedFileAppears) {
  const fs::path d = ahd_test::temp_dir("cook_direct");
  const GodotSet g(d, 1);
  const std::string lmbake = ahd_test::read_text(d / "World.lmbake");
  fs::remove(d / "World.lmbake");
  const std::vector<std::string> args = {"convert", g.exr, "--normals", g.normals, "-o", (d / "o" / "w.ktx2").string(),
                                         "--cache", (d / "cache").string(), "--depfile", (d / "o" / "w.d").string()};
  auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "cache: stored")) << r.output;
  const std::string deps = ahd_test::read_text(d / "o" / "w.d");
  EXPECT_FALSE(contains(deps, "World.lmbake")) << deps;
  r = run_cli(args);
  EXPECT_TRUE(contains(r.output, "cache hit")) << r.output;
  EXPECT_EQ(ahd_test::read_text(d / "o" / "w.d"), deps);  // the direct hit names the same files
  spit(d / "World.lmbake", lmbake);
  r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "World.lmbake: has _uses_packed_directional")) << r.output;  // read again
  EXPECT_TRUE(contains(r.output, "cache: stored")) << r.output;
  EXPECT_TRUE(contains(ahd_test::read_text(d / "o" / "w.d"), "World.lmbake"));
  fs::remove_all(d);
}

// Two processes (each a batch converting four inputs side by side) fill one cache at once.
TEST(Cook, TwoProcessesFillingOneCacheLeaveItConsistent) {
  const fs::path d = ahd_test::temp_dir("cook_concurrent");
  fs::create_directories(d / "in");
  for (int s = 1; s <= 4; ++s)
    ASSERT_EQ(run_cli({"sample", "--size", "32", "--seed", std::to_string(s), "-o", (d / "in" / ("s" + std::to_string(s) + ".exr")).string()})
                  .exit_code,
              0);
  const std::string cache = (d / "cache").string();
  const auto batch = [&](const std::string& out) {
    return "'" + std::string(AHD_CLI_PATH) + "' convert '" + (d / "in").string() + "' -o '" + (d / out).string() +
           "/' --profile pc-bc -q --cache '" + cache + "'";
  };
  const std::string out = ahd_test::run_shell("(" + batch("p1") + ") & (" + batch("p2") + ") & wait %1; a=$?; wait %2; echo rc=$a,$?");
  ASSERT_EQ(out, "rc=0,0\n");
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(cache)) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() == ".ahdinputs") {  // what each command read (the direct lookup)
      EXPECT_TRUE(ConversionCache(cache, 0).lookup_inputs(e.path().stem().string())) << name;
      continue;
    }
    EXPECT_EQ(e.path().extension(), ".ahdcache") << name << " left behind";
    const std::string bytes = ahd_test::read_text(e.path());
    EXPECT_TRUE(ConversionCache::decode(e.path().stem().string(), std::vector<uint8_t>(bytes.begin(), bytes.end()))) << name;
    ++entries;
  }
  EXPECT_EQ(entries, 4u);
  const auto p1 = folder_files(d / "p1"), p2 = folder_files(d / "p2");
  EXPECT_EQ(p1.size(), 20u);  // 4 x (3 planes, manifest, report)
  for (const auto& [name, bytes] : p1)
    if (name.find(".report.json") == std::string::npos) EXPECT_EQ(p2.at(name), bytes) << name;
  // A third run is all hits, and writes the same planes and manifests.
  const auto r = run_cli({"convert", (d / "in").string(), "-o", (d / "p3").string() + "/", "--profile", "pc-bc", "--cache", cache});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const auto& [name, bytes] : folder_files(d / "p3"))
    if (name.find(".report.json") == std::string::npos) EXPECT_EQ(p1.at(name), bytes) << name;
  fs::remove_all(d);
}

TEST(Cook, CacheEvictsTheLeastRecentlyUsedPastItsBound) {
  const fs::path d = ahd_test::temp_dir("cook_evict");
  const auto key = [](char c) { return std::string(64, c); };
  const std::vector<OutputFile> files = {{"x.json", std::vector<uint8_t>(1000, 7)}};
  const uint64_t entry = ConversionCache::encode(key('a'), files).size();
  const ConversionCache cache(d.string(), 2 * entry + entry / 2);  // room for two
  const auto age = [&](char c, int minutes) {
    fs::last_write_time(cache.entry_path(key(c)), fs::file_time_type::clock::now() - std::chrono::minutes(minutes));
  };
  cache.store(key('a'), files);
  age('a', 30);
  cache.store(key('b'), files);
  age('b', 20);
  ASSERT_TRUE(cache.lookup(key('a')));  // a used again: b is now the least recently used
  const CacheStats st = cache.store(key('c'), files);
  EXPECT_EQ(st.evicted, 1u);
  EXPECT_EQ(st.entries, 2u);
  EXPECT_TRUE(cache.lookup(key('a')));
  EXPECT_FALSE(cache.lookup(key('b')));
  EXPECT_TRUE(cache.lookup(key('c')));
  // Entries are checked, whatever their name says.
  EXPECT_FALSE(ConversionCache::decode(key('c'), ConversionCache::encode(key('a'), files)));
  EXPECT_THROW(ConversionCache::encode(key('a'), {{"../x.json", {1}}}), Error);
  EXPECT_EQ(parse_byte_size("512M", "--cache-max-size"), uint64_t(512) << 20);
  EXPECT_THROW(parse_byte_size("12X", "--cache-max-size"), Error);
  fs::remove_all(d);
}

TEST(Cook, VerifyReadsTheBakersFilesAsConvertDoes) {
  const fs::path d = ahd_test::temp_dir("cook_verify");
  const GodotSet g(d, 4);
  const std::string manifest = (d / "o" / "atlas.json").string();
  ASSERT_EQ(run_cli({"convert", g.exr, "--normals", g.normals, "-o", (d / "o" / "atlas.ktx2").string(), "-q"}).exit_code, 0);
  auto r = run_cli({"verify", manifest, "--source", g.exr, "--normals", g.normals});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "page 3 against")) << r.output;
  EXPECT_TRUE(contains(r.output, "12 of 12 checks passed")) << r.output;
  // The wrong normals: the world-space SH read with them is another signal, and verify says so.
  const fs::path flat = d / "flat.exr";
  ImageF n = read_image(g.normals);
  for (size_t i = 0; i < n.data.size(); i += 3) n.data[i] = 1, n.data[i + 1] = 0, n.data[i + 2] = 0;
  write_image(flat.string(), n);
  r = run_cli({"verify", manifest, "--source", g.exr, "--normals", flat.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "FAIL")) << r.output;
  // A single-page source against the 4-page conversion: one error line.
  const GodotSet one(d / "one", 1);
  r = run_cli({"verify", manifest, "--source", one.exr, "--normals", one.normals});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "holds 1 atlas page(s), the conversion 4")) << r.output;
  fs::remove_all(d);
}

// The done-when of issue 31: a CMake project built with Ninja cooks three lightmaps through the
// installed ahdpack_add_lightmaps; a second build does nothing; touching one input's .exr.import,
// then another input, reconverts only that one; the outputs equal a direct `ahdpack convert`.
TEST(Cook, CmakeNinjaCooksOnlyWhatChanged) {
  if (ahd_test::run_shell("command -v ninja >/dev/null && command -v cmake >/dev/null; echo $?") != "0\n")
    GTEST_SKIP() << "ninja or cmake not installed";
  const fs::path d = ahd_test::temp_dir("cook_cmake");
  ASSERT_EQ(run_cli({"sample", "--size", "32", "--seed", "1", "-o", (d / "a.exr").string()}).exit_code, 0);
  ASSERT_EQ(run_cli({"sample", "--size", "32", "--seed", "2", "-o", (d / "b.exr").string()}).exit_code, 0);
  const GodotSet g(d, 1, "world");
  const std::string build = fs::path(AHD_CLI_PATH).parent_path().string();
  const std::string out = ahd_test::run_shell("bash '" + std::string(AHD_SOURCE_DIR) + "/tests/cook/run.sh' '" + build + "' '" +
                                              AHD_CLI_PATH + "' '" + d.string() + "' 2>&1; echo rc=$?");
  EXPECT_TRUE(contains(out, "first build cooked: a b world")) << out;
  EXPECT_TRUE(contains(out, "second build: no work to do")) << out;
  EXPECT_TRUE(contains(out, "after touching world.exr.import cooked: world \n")) << out;
  EXPECT_TRUE(contains(out, "after touching a.exr cooked: a \n")) << out;
  EXPECT_TRUE(contains(out, "files identical to a direct ahdpack convert")) << out;
  EXPECT_TRUE(contains(out, "rc=0\n")) << out;
  fs::remove_all(d);
}

namespace {

TEST(Cook, GodotSceneDepfileNamesTheProjectFilesItRead) {
  // The real Godot 4.2 project: the conversion reads world.tscn, the scenes it instances, the
  // .lmbake, each .glb and its .unwrap_cache; all are inputs a build must know of.
  const fs::path bake = ahd_test::test_data("bakes/godot42-vermilion/project/scenes");
  AHD_REQUIRE_DATA(bake / "world.exr");
  const fs::path out = ahd_test::temp_dir("cook_godot_scene");
  const auto r = run_cli({"convert", (bake / "world.exr").string(), "-o", (out / "w.ktx2").string(), "--depfile",
                          (out / "w.d").string(), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::set<std::string> deps = depfile_deps(out / "w.d");
  for (const char* f : {"world.exr", "world.exr.import", "world.tscn", "world.lmbake"})
    EXPECT_TRUE(deps.count(abs_path(bake / f))) << f << " missing from\n" << ahd_test::read_text(out / "w.d");
  size_t glb = 0, unwrap = 0;
  for (const std::string& dep : deps) {
    glb += dep.size() > 4 && dep.compare(dep.size() - 4, 4, ".glb") == 0;
    unwrap += dep.find(".glb.unwrap_cache") != std::string::npos;
    EXPECT_TRUE(fs::is_regular_file(dep)) << dep;
  }
  EXPECT_GT(glb, 5u) << ahd_test::read_text(out / "w.d");
  EXPECT_EQ(unwrap, glb) << "every mesh's UV2 comes from its unwrap cache";
  fs::remove_all(out);
}

}  // namespace

// `verify --source` and `preview --source` on a real Godot project (tests/data/bakes/godot42-vermilion):
// the source read as convert reads it (layout detected, the scene, meshes and .lmbake found), the
// default bounds passing fresh conversions (README's command, uncompressed, --iz-scale E/pi) and
// failing a corrupted iz plane, a conversion without its direction planes, a manifest whose
// iz_scale is not the planes' and (against a golden) a changed profile.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "containers/sha256.h"
#include "file_bytes.h"
#include "test_data.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

const fs::path kWorld = ahd_test::test_data("bakes/godot42-vermilion/project/scenes/world.exr");

double figure(const std::string& out, const std::string& check) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex("(PASS|FAIL)  " + check + " +([0-9.e+-]+|inf|nan) <="))) return -1;
  return std::stod(m[2]);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Converts the vermilion project with the README's command and `extra`; returns the manifest.
fs::path convert(const fs::path& dir, const std::string& tag, std::vector<std::string> extra) {
  const fs::path out = dir / tag / "world.ktx2";
  std::vector<std::string> args = {"convert", kWorld.string(), "-o", out.string(), "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return dir / tag / "world.json";
}

// A copy of the conversion whose iz plane has bytes flipped (XOR 0xFF) over the middle tenth of its
// level 0, with the manifest's SHA-256 of the plane updated: a consistent set whose decode is wrong,
// so only the error bounds can tell.
fs::path corrupted_iz(const fs::path& manifest, const fs::path& dir) {
  fs::create_directories(dir);
  nlohmann::json j = nlohmann::json::parse(ahd_test::read_text(manifest));
  for (auto& p : j["planes"]) {
    const std::string file = p["file"].get<std::string>();
    std::vector<uint8_t> b = ahd_test::slurp(manifest.parent_path() / file);
    if (p["name"] == "iz") {
      // KTX2: the level index starts at byte 80, level 0 first (u64 byteOffset, u64 byteLength).
      EXPECT_GT(b.size(), 96u);
      uint64_t off = 0, len = 0;
      for (int i = 0; i < 8; ++i) off |= uint64_t(b[80 + i]) << (8 * i), len |= uint64_t(b[88 + i]) << (8 * i);
      EXPECT_LE(off + len, b.size());
      for (uint64_t i = off + len * 45 / 100; i < off + len * 55 / 100; ++i) b[i] ^= 0xFF;
      p["sha256"] = ahd::sha256_hex(b.data(), b.size());
    }
    ahd_test::spit(dir / file, b);
  }
  ahd_test::spit(dir / "world.json", j.dump(2));
  return dir / "world.json";
}

}  // namespace

TEST(Verify, GodotProjectPassesFreshConversionsAtTheDefaultBounds) {
  AHD_REQUIRE_DATA(kWorld);
  const fs::path dir = ahd_test::temp_dir("verify_godot");
  // The README's command (pc-bc), uncompressed, and pc-bc storing E/π.
  const fs::path bc = convert(dir, "bc", {"--profile", "pc-bc"});
  const fs::path raw = convert(dir, "raw", {"--profile", "uncompressed"});
  const fs::path pi = convert(dir, "pi", {"--profile", "pc-bc", "--iz-scale", "E/pi"});
  double bc_rel = -1;
  for (const fs::path& m : {bc, raw, pi}) {
    const auto r = run_cli({"verify", m.string(), "--source", kWorld.string()});
    EXPECT_EQ(r.exit_code, 0) << m << "\n" << r.output;
    // Read as convert read it: the Godot layout detected and the scene found beside the EXR.
    EXPECT_TRUE(contains(r.output, "(layout godot4-")) << r.output;
    EXPECT_TRUE(contains(r.output, "world.tscn")) << r.output;
    for (const char* check : {"rel-p99", "log-rmse", "iz-rel-p99"}) {
      const double v = figure(r.output, check);
      EXPECT_GE(v, 0.0) << check << "\n" << r.output;
      EXPECT_TRUE(contains(r.output, std::string("PASS  ") + check)) << r.output;
    }
    if (m == bc) bc_rel = figure(r.output, "rel-p99");
    // E/π: the manifest's iz_scale is undone before measuring, so the figures are those of E.
    if (m == pi) EXPECT_NEAR(figure(r.output, "rel-p99"), bc_rel, 0.02 + 0.1 * bc_rel) << r.output;
  }
  // Without the floor (the per-texel relative error of the report) the near-black texels dominate:
  // the figure this measure replaces, far above the bound on the same conversion.
  const auto plain = run_cli({"verify", bc.string(), "--source", kWorld.string(), "--dark-floor", "0"});
  EXPECT_EQ(plain.exit_code, 1) << plain.output;
  EXPECT_GT(figure(plain.output, "rel-p99"), 2 * bc_rel) << plain.output;
  // A changed profile against the golden README conversion: the layout check names it.
  const auto golden = run_cli({"verify", raw.string(), "--golden", bc.string()});
  EXPECT_EQ(golden.exit_code, 1) << golden.output;
  EXPECT_TRUE(contains(golden.output, "FAIL  golden-layout")) << golden.output;
  EXPECT_TRUE(contains(golden.output, "differs: profile")) << golden.output;
  fs::remove_all(dir);
}

TEST(Verify, GodotProjectFailsACorruptedPlaneAndADroppedDirection) {
  AHD_REQUIRE_DATA(kWorld);
  const fs::path dir = ahd_test::temp_dir("verify_godot_bad");
  for (const char* profile : {"uncompressed", "pc-bc"}) {
    const fs::path m = convert(dir, profile, {"--profile", profile, "--levels", "1"});
    auto r = run_cli({"verify", m.string(), "--source", kWorld.string()});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const fs::path bad = corrupted_iz(m, dir / (std::string(profile) + "_corrupt"));
    r = run_cli({"verify", bad.string(), "--source", kWorld.string()});
    EXPECT_EQ(r.exit_code, 1) << profile << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, "FAIL  rel-p99")) << r.output;
    EXPECT_TRUE(contains(r.output, "FAIL  iz-rel-p99")) << r.output;
    EXPECT_FALSE(contains(r.output, "ahdpack: error")) << r.output;  // a failed check, not bad input
  }
  // A changed option: the direction planes dropped (I_z alone) on this directional bake.
  const fs::path drop = convert(dir, "drop", {"--profile", "pc-bc", "--levels", "1", "--direction", "drop"});
  auto r = run_cli({"verify", drop.string(), "--source", kWorld.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "FAIL  rel-p99")) << r.output;
  // A changed profile or scale the manifest does not record: the iz plane of an E/π conversion
  // under a manifest saying E (plane files and hashes as written), so I_z is 1/π of the source's.
  const fs::path pi = convert(dir, "pi", {"--profile", "pc-bc", "--levels", "1", "--iz-scale", "E/pi"});
  nlohmann::json j = nlohmann::json::parse(ahd_test::read_text(pi));
  j["decode"]["iz_scale"] = 1.0;
  ahd_test::spit(pi, j.dump(2));
  r = run_cli({"verify", pi.string(), "--source", kWorld.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "FAIL  iz-rel-p99")) << r.output;
  fs::remove_all(dir);
}

TEST(Preview, GodotProjectSourceGivesHeatMaps) {
  AHD_REQUIRE_DATA(kWorld);
  const fs::path dir = ahd_test::temp_dir("preview_godot");
  const fs::path m = convert(dir, "c", {"--profile", "pc-bc", "--levels", "1"});
  const auto r = run_cli({"preview", m.string(), "--source", kWorld.string(), "-o", (dir / "page").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "error heat maps against the source")) << r.output;
  for (const char* f : {"error_normal.png", "error_hemisphere.png", "index.html"})
    EXPECT_TRUE(fs::is_regular_file(dir / "page" / f)) << f;
  const std::string html = ahd_test::read_text(dir / "page" / "index.html");
  EXPECT_TRUE(contains(html, "Error against the source SH")) << html.substr(0, 2000);
  EXPECT_TRUE(contains(html, "(layout godot4-")) << html.substr(0, 2000);
  fs::remove_all(dir);
}

// StableNames.*: `convert --stable-names` (ConversionOptions::stable_names) names the planes
// NAME.<plane>.<ext>, the same at every re-cook, and keeps the publication's guarantees
// (docs/asset-cook.md "Stable names for engines"): each plane whole under its name, the previous
// set back on an error, a plane beside the manifest always the one it names (or missing after a
// kill), the clean-up removing only the previous set's own planes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "cli_runner.h"
#include "containers/sha256.h"
#include "file_bytes.h"
#include "files/manifest_file.h"
#include "pipeline/manifest.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

ahd_test::CliResult cook(const fs::path& out, int seed, const std::string& profile, bool stable,
                         std::vector<std::string> extra = {}) {
  std::vector<std::string> a = {"convert", "-o", out.string(), "--sample-size", "16", "--profile", profile,
                                "--seed", std::to_string(seed), "-q"};
  if (stable) a.push_back("--stable-names");
  a.insert(a.end(), extra.begin(), extra.end());
  return run_cli(a);
}

std::string sha_of(const fs::path& p) {
  const std::string s = ahd_test::read_text(p);
  return ahd::sha256_hex(reinterpret_cast<const uint8_t*>(s.data()), s.size());
}

// Every plane file the manifest names that is present has the manifest's SHA-256; returns how many
// are missing.
int planes_missing(const fs::path& manifest, bool* all_match) {
  *all_match = true;
  int missing = 0;
  for (const ahd::ManifestPlane& p : ahd::read_manifest_file(manifest.string()).planes) {
    const fs::path f = manifest.parent_path() / p.file;
    if (!fs::exists(f)) {
      ++missing;
      continue;
    }
    if (sha_of(f) != p.sha256) *all_match = false;
  }
  return missing;
}

std::set<std::string> set_files(const fs::path& dir, const std::string& name) {
  std::set<std::string> s = {name + ".json", name + ".report.json"};
  for (const auto& p : ahd::read_manifest_file((dir / (name + ".json")).string()).planes) s.insert(p.file);
  return s;
}

}  // namespace

TEST(StableNames, ReCookKeepsTheNamesAndReplacesTheContent) {
  const fs::path d = ahd_test::temp_dir("stable_names_recook");
  ASSERT_EQ(cook(d / "world.ktx2", 1, "pc-bc", true).exit_code, 0);
  const std::set<std::string> first = ahd_test::names_in(d);
  EXPECT_EQ(first, (std::set<std::string>{"world.json", "world.report.json", "world.iz.ktx2", "world.dir.ktx2",
                                          "world.ratio.ktx2"}));
  const std::string iz1 = sha_of(d / "world.iz.ktx2");
  ASSERT_EQ(cook(d / "world.ktx2", 2, "pc-bc", true).exit_code, 0);  // other lighting, same names
  EXPECT_EQ(ahd_test::names_in(d), first);
  EXPECT_NE(sha_of(d / "world.iz.ktx2"), iz1);
  bool match = false;
  EXPECT_EQ(planes_missing(d / "world.json", &match), 0);
  EXPECT_TRUE(match);
  // The bytes are those of the content-addressed conversion; only the names differ.
  const fs::path h = ahd_test::temp_dir("stable_names_hashed");
  ASSERT_EQ(cook(h / "world.ktx2", 2, "pc-bc", false).exit_code, 0);
  const ahd::Manifest hm = ahd::read_manifest_file((h / "world.json").string());
  const ahd::Manifest sm = ahd::read_manifest_file((d / "world.json").string());
  ASSERT_EQ(hm.planes.size(), sm.planes.size());
  for (size_t i = 0; i < hm.planes.size(); ++i) {
    EXPECT_EQ(hm.planes[i].sha256, sm.planes[i].sha256);
    EXPECT_EQ(sm.planes[i].file, "world." + sm.planes[i].name + ".ktx2");
    EXPECT_NE(hm.planes[i].file, sm.planes[i].file);
  }
  // `decode` reads the set as it reads any other.
  const fs::path e = ahd_test::temp_dir("stable_names_decode");
  const auto r = run_cli({"decode", (d / "world.json").string(), "-o", (e / "e.exr").string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  fs::remove_all(e);
  // The option is part of the key: a cached hashed entry never publishes under stable names.
  const auto k1 = cook(d / "world.ktx2", 2, "pc-bc", true, {"--print-key"}), k2 = cook(d / "world.ktx2", 2, "pc-bc", false, {"--print-key"});
  ASSERT_EQ(k1.exit_code, 0) << k1.output;
  EXPECT_NE(k1.output, k2.output);
  fs::remove_all(d);
  fs::remove_all(h);
}

// Killed before every rename in turn: the manifest beside the planes is one run's, and every plane
// beside it is the one it names (its SHA-256) or missing; the next run leaves exactly its set.
TEST(StableNames, KilledAtEveryRenameNeverPairsAManifestWithAnotherRunsPlane) {
  const fs::path root = ahd_test::temp_dir("stable_names_kill");
  size_t saw_missing = 0, saw_new = 0;
  for (int k = 0;; ++k) {
    ASSERT_LT(k, 30) << "the hook never stopped killing";
    SCOPED_TRACE("killed before rename " + std::to_string(k));
    const fs::path d = root / ("k" + std::to_string(k));
    ASSERT_EQ(cook(d / "world.ktx2", 1, "pc-bc", true).exit_code, 0);
    const std::string old_manifest = ahd_test::read_text(d / "world.json");
    ::setenv("AHDPACK_TEST_KILL_BEFORE_RENAME", std::to_string(k).c_str(), 1);
    const auto killed = cook(d / "world.ktx2", 2, "pc-bc", true);
    ::unsetenv("AHDPACK_TEST_KILL_BEFORE_RENAME");
    bool match = false;
    const int missing = planes_missing(d / "world.json", &match);
    EXPECT_TRUE(match) << "a plane beside the manifest is another run's";
    saw_missing += missing > 0;
    saw_new += ahd_test::read_text(d / "world.json") != old_manifest;
    ASSERT_EQ(cook(d / "world.ktx2", 2, "pc-bc", true).exit_code, 0);
    EXPECT_EQ(planes_missing(d / "world.json", &match), 0);
    EXPECT_TRUE(match);
    EXPECT_EQ(ahd_test::names_in(d), set_files(d, "world"));  // no temporaries, no moved-aside planes
    if (killed.exit_code == 0) break;  // k passed the last rename and the clean-up
  }
  EXPECT_GT(saw_new, 0u);
  EXPECT_GT(saw_missing, 0u);  // the price of fixed names: for an instant a plane is missing
  fs::remove_all(root);
}

// From hashed to stable names and back, and to a profile with other planes: the previous set's
// planes go, a user's file of a plane-like name that no manifest names stays.
TEST(StableNames, SwitchingNamingRemovesThePreviousPlanes) {
  const fs::path d = ahd_test::temp_dir("stable_names_switch");
  ASSERT_EQ(cook(d / "world.ktx2", 1, "pc-bc", false).exit_code, 0);
  ASSERT_EQ(cook(d / "world.ktx2", 1, "pc-bc", true).exit_code, 0);
  EXPECT_EQ(ahd_test::names_in(d), set_files(d, "world"));
  ASSERT_EQ(cook(d / "world.ktx2", 1, "packed-rgb9e5", true).exit_code, 0);  // iz + dirratio: ratio and dir go
  EXPECT_EQ(ahd_test::names_in(d), set_files(d, "world"));
  EXPECT_FALSE(fs::exists(d / "world.ratio.ktx2"));
  std::ofstream(d / "world.coverage.ktx2") << "not ahdpack's";
  ASSERT_EQ(cook(d / "world.ktx2", 1, "pc-bc", false).exit_code, 0);
  std::set<std::string> want = set_files(d, "world");
  want.insert("world.coverage.ktx2");
  EXPECT_EQ(ahd_test::names_in(d), want);
  EXPECT_EQ(ahd_test::read_text(d / "world.coverage.ktx2"), "not ahdpack's");
  fs::remove_all(d);
}

// A cache hit publishes the stored files as the conversion does: the same stable names and bytes.
TEST(StableNames, CacheHitPublishesTheStableNames) {
  const fs::path d = ahd_test::temp_dir("stable_names_cache");
  const std::string cache = (d / "cache").string();
  ASSERT_EQ(cook(d / "a" / "world.ktx2", 1, "pc-bc", true, {"--cache", cache}).exit_code, 0);  // a miss: stored
  const auto hit = run_cli({"convert", "-o", (d / "b" / "world.ktx2").string(), "--sample-size", "16", "--profile", "pc-bc",
                            "--seed", "1", "--stable-names", "--cache", cache});
  ASSERT_EQ(hit.exit_code, 0) << hit.output;
  EXPECT_NE(hit.output.find("cache hit"), std::string::npos) << hit.output;
  EXPECT_EQ(ahd_test::names_in(d / "b"), ahd_test::names_in(d / "a"));
  EXPECT_TRUE(fs::exists(d / "b" / "world.iz.ktx2"));
  for (const std::string f : {"world.json", "world.iz.ktx2", "world.dir.ktx2", "world.ratio.ktx2"})
    EXPECT_EQ(ahd_test::read_text(d / "b" / f), ahd_test::read_text(d / "a" / f)) << f;
  // The hashed conversion of the same input is another entry (the key has stable_names 1).
  const auto hashed = cook(d / "c" / "world.ktx2", 1, "pc-bc", false, {"--cache", cache});
  ASSERT_EQ(hashed.exit_code, 0) << hashed.output;
  EXPECT_FALSE(fs::exists(d / "c" / "world.iz.ktx2"));
  fs::remove_all(d);
}

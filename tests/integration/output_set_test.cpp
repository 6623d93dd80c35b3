// Output sets published whole or not at all (issue 15): a conversion killed before any rename, or
// failing on a full disk, leaves the previous set complete and readable under the final names; the
// next run removes the temporaries and the superseded planes.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "files/manifest_file.h"
#include "files/container_file.h"
#include "files/profile_file.h"
#include "cli_runner.h"
#include "core/error.h"
#include "files/output_set.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "file_bytes.h"
#include <nlohmann/json.hpp>

namespace fs = std::filesystem;
using namespace ahd;

namespace {

std::map<std::string, std::string> snapshot_files(const fs::path& d) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(d))
    if (e.is_regular_file()) m[e.path().filename().string()] = ahd_test::read_text(e.path());
  return m;
}

size_t temporaries_in(const fs::path& d) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(d)) n += is_temporary_name(e.path().filename().string());
  return n;
}

// Reads the set as `ahdpack decode` does: every plane's size and hash verified, then decoded.
void expect_complete_set(const fs::path& manifest) {
  const Manifest m = read_manifest_file(manifest.string());
  std::vector<Plane> planes;
  for (const auto& mp : m.planes) planes.push_back({mp.name, read_manifest_plane(manifest.string(), mp)});
  const DecodedPlanes p = decode_planes(planes, m.ratio_form == RatioForm::Rgb, 0);
  EXPECT_EQ(uint32_t(p.width), m.width);
}

ahd_test::CliResult convert_set(const fs::path& d, const std::string& profile) {
  return ahd_test::run_cli({"convert", "-o", (d / "room.ktx2").string(), "--sample-size", "16", "--profile", profile, "-q"});
}

// The plane, report and manifest files of a set: what the folder must hold after a clean run.
std::set<std::string> manifest_set_files(const fs::path& manifest) {
  std::set<std::string> s = {manifest.filename().string(), "room.report.json"};
  for (const auto& p : read_manifest_file(manifest.string()).planes) s.insert(p.file);
  return s;
}

}  // namespace

// Issue 15, case 4: kill -9 between renames. SIGKILL is injected before each rename in turn
// (AHDPACK_TEST_KILL_BEFORE_RENAME) while pc-bc replaces an uncompressed set. Before the
// manifest's rename the old set must be complete; after it the new one; never a mix.
TEST(OutputSet, KilledBeforeEachRenameLeavesOldOrNewSetCompleteAndNextRunCleansUp) {
  const fs::path root = ahd_test::temp_dir("output_set_kill");
  const fs::path ref_old = root / "ref_old", ref_new = root / "ref_new";
  fs::create_directories(ref_old);
  fs::create_directories(ref_new);
  ASSERT_EQ(convert_set(ref_old, "uncompressed").exit_code, 0);
  ASSERT_EQ(convert_set(ref_new, "pc-bc").exit_code, 0);
  const std::string old_manifest = ahd_test::read_text(ref_old / "room.json"), new_manifest = ahd_test::read_text(ref_new / "room.json");
  ASSERT_NE(old_manifest, new_manifest);
  const size_t renames = manifest_set_files(ref_new / "room.json").size();  // planes, report, manifest
  for (size_t k = 0; k <= renames; ++k) {
    SCOPED_TRACE("killed before rename " + std::to_string(k));
    const fs::path d = root / ("k" + std::to_string(k));
    fs::create_directories(d);
    ASSERT_EQ(convert_set(d, "uncompressed").exit_code, 0);
    ::setenv("AHDPACK_TEST_KILL_BEFORE_RENAME", std::to_string(k).c_str(), 1);
    const auto killed = convert_set(d, "pc-bc");
    ::unsetenv("AHDPACK_TEST_KILL_BEFORE_RENAME");
    EXPECT_TRUE(killed.exit_code == 128 + SIGKILL || killed.exit_code == -1) << "not killed: " << killed.output;
    const std::string now = ahd_test::read_text(d / "room.json");
    // The manifest is renamed last (index renames - 1): before it the old set, after it the new.
    EXPECT_EQ(now, k < renames ? old_manifest : new_manifest);
    expect_complete_set(d / "room.json");
    if (k < renames) {
      EXPECT_GT(temporaries_in(d), 0u) << "the kill left no temporaries: the hook did not fire?";
    }
    // The next run publishes its set and leaves exactly that set: no temporary, no old plane.
    ASSERT_EQ(convert_set(d, "pc-bc").exit_code, 0);
    EXPECT_EQ(temporaries_in(d), 0u);
    EXPECT_EQ(ahd_test::names_in(d), manifest_set_files(d / "room.json"));
    EXPECT_EQ(ahd_test::read_text(d / "room.json"), new_manifest);
    expect_complete_set(d / "room.json");
  }
  fs::remove_all(root);
}

// Issue 15, case 3: a conversion failing on a full disk (simulated: AHDPACK_TEST_WRITE_FAULT)
// used to delete a plane of the previous set. Now: one error line naming the file, exit 1, and
// the previous set byte for byte, with no temporary file left.
TEST(OutputSet, FailedConversionLeavesThePreviousSetUntouched) {
  const fs::path d = ahd_test::temp_dir("output_set_fail");
  ASSERT_EQ(convert_set(d, "uncompressed").exit_code, 0);
  const auto before = snapshot_files(d);
  for (const char* fault : {"0:ENOSPC", "1:ENOSPC", "3:EROFS", "4:ENOSPC"}) {
    SCOPED_TRACE(fault);
    ::setenv("AHDPACK_TEST_WRITE_FAULT", fault, 1);
    const auto r = convert_set(d, "pc-bc");
    ::unsetenv("AHDPACK_TEST_WRITE_FAULT");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.rfind("ahdpack: error: " + d.string() + "/room.", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_EQ(snapshot_files(d), before);
    EXPECT_EQ(temporaries_in(d), 0u);
    expect_complete_set(d / "room.json");
  }
  fs::remove_all(d);
}

// In-process: a failure anywhere before the manifest's rename removes every temporary and every
// file the failed publish created, and keeps files it replaced with identical bytes.
TEST(OutputSet, PublishIsAllOrNothingInProcess) {
  const fs::path d = ahd_test::temp_dir("output_set_unit");
  std::vector<FileToPublish> files = {{(d / "a.iz.0.ktx2").string(), {1, 2, 3}},
                                   {(d / "a.dir.0.ktx2").string(), {4, 5}},
                                   {(d / "a.json").string(), {'{', '}'}}};
  publish_output_set(files);
  EXPECT_EQ(ahd_test::read_text(d / "a.json"), "{}");
  const auto before = snapshot_files(d);
  std::vector<FileToPublish> next = {{(d / "a.iz.1.ktx2").string(), {9}}, {(d / "a.json").string(), {'[', ']'}}};
  ::setenv("AHDPACK_TEST_WRITE_FAULT", "1:ENOSPC", 1);
  EXPECT_THROW(publish_output_set(next), Error);
  ::unsetenv("AHDPACK_TEST_WRITE_FAULT");
  EXPECT_EQ(snapshot_files(d), before);
  // A folder in the way of the manifest: refused before anything is written.
  fs::create_directories(d / "b.json");
  try {
    publish_output_set({{(d / "b.iz.ktx2").string(), {1}}, {(d / "b.json").string(), {2}}});
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), (d / "b.json").string() + ": is a folder");
  }
  EXPECT_EQ(snapshot_files(d), before);
  // Superseded files go once the new manifest is in place; the published ones stay.
  publish_output_set(next, {(d / "a.iz.0.ktx2").string(), (d / "a.dir.0.ktx2").string(), (d / "a.iz.1.ktx2").string()});
  EXPECT_FALSE(fs::exists(d / "a.iz.0.ktx2"));
  EXPECT_FALSE(fs::exists(d / "a.dir.0.ktx2"));
  EXPECT_EQ(ahd_test::read_text(d / "a.iz.1.ktx2"), "\x09");
  EXPECT_EQ(ahd_test::read_text(d / "a.json"), "[]");
  fs::remove_all(d);
}

// Stale temporaries of a dead process are removed; those of a live one (another ahdpack writing
// into the same folder) are kept.
TEST(OutputSet, StaleTemporariesOfDeadProcessesAreRemoved) {
  const fs::path d = ahd_test::temp_dir("output_set_stale");
  long dead = 4194000;
  while (::kill(pid_t(dead), 0) == 0 || errno != ESRCH) --dead;
  const std::string dead_tmp = ".room.json.ahdtmp-" + std::to_string(dead) + "-0badf00d.json";
  const std::string live_tmp = ".room.json.ahdtmp-" + std::to_string(::getpid()) + "-0badf00d.json";
  std::ofstream(d / dead_tmp) << "x";
  std::ofstream(d / live_tmp) << "x";
  std::ofstream(d / "room.ahdtmp.notours") << "x";
  EXPECT_TRUE(is_temporary_name(dead_tmp));
  EXPECT_FALSE(is_temporary_name("room.ahdtmp.notours"));
  ASSERT_EQ(convert_set(d, "uncompressed").exit_code, 0);
  EXPECT_FALSE(fs::exists(d / dead_tmp));
  EXPECT_TRUE(fs::exists(d / live_tmp));
  EXPECT_TRUE(fs::exists(d / "room.ahdtmp.notours"));
  fs::remove_all(d);
}

// Issue 44: clean-up removed every plain-named file the previous manifest named. A stale or
// crafted room.json naming README.md and other.json (even with their exact sizes and hashes) and a
// plane of the right name edited since: all kept; the previous set's own planes still go.
TEST(OutputSet, CleanUpDeletesOnlyPlanesItWroteForTheStem) {
  const fs::path d = ahd_test::temp_dir("output_set_crafted");
  const std::string readme_md = std::string("READ") + "ME.md";
  ASSERT_EQ(convert_set(d, "uncompressed").exit_code, 0);
  nlohmann::json m = nlohmann::json::parse(ahd_test::read_text(d / "room.json"));
  ASSERT_GE(m["planes"].size(), 3u);
  // README.md and other.json hold planes 0 and 1's bytes, so their sizes and SHA-256 match.
  const fs::path plane0 = d / m["planes"][0]["file"].get<std::string>(), plane1 = d / m["planes"][1]["file"].get<std::string>();
  fs::copy_file(plane0, d / readme_md);
  fs::copy_file(plane1, d / "other.json");
  m["planes"][0]["file"] = readme_md;
  m["planes"][1]["file"] = "other.json";
  // Plane 2 keeps its name but its content changed (same size): not the file the manifest recorded.
  const fs::path edited = d / m["planes"][2]["file"].get<std::string>();
  std::string bytes = ahd_test::read_text(edited);
  bytes.back() ^= 1;
  std::ofstream(edited, std::ios::binary | std::ios::trunc) << bytes;
  std::ofstream(d / "room.json", std::ios::trunc) << m.dump(2);
  const std::string readme = ahd_test::read_text(d / readme_md), other = ahd_test::read_text(d / "other.json");
  ASSERT_EQ(convert_set(d, "pc-bc").exit_code, 0);
  EXPECT_EQ(ahd_test::read_text(d / readme_md), readme);
  EXPECT_EQ(ahd_test::read_text(d / "other.json"), other);
  EXPECT_EQ(ahd_test::read_text(edited), bytes);
  // The stem's own plane files, untouched and now named by no manifest, still go.
  EXPECT_FALSE(fs::exists(plane0));
  EXPECT_FALSE(fs::exists(plane1));
  const std::set<std::string> set_files = manifest_set_files(d / "room.json");
  for (const auto& e : fs::directory_iterator(d)) {
    const std::string fn = e.path().filename().string();
    if (!set_files.count(fn)) EXPECT_TRUE(fn == readme_md || fn == "other.json" || e.path() == edited) << fn;
  }
  fs::remove_all(d);
}

// Issue 44: `-o room.report.ktx2` wrote room.report.json as its manifest, the report of the set
// "room" beside it: each run replaced the other's file. A stem ending in ".report" is refused up
// front (one line, nothing written), as are control characters and stems over 200 bytes.
TEST(OutputSet, SetsInOneFolderNeverShareAFileName) {
  const fs::path d = ahd_test::temp_dir("output_set_report_stem");
  ASSERT_EQ(convert_set(d, "uncompressed").exit_code, 0);
  const auto before = snapshot_files(d);
  for (const std::string& name : {std::string("room.report.ktx2"), std::string("a\nb.ktx2"), std::string(201, 'r') + ".ktx2"}) {
    const auto r = ahd_test::run_cli({"convert", "-o", (d / name).string(), "--sample-size", "16", "-q"});
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.rfind("ahdpack: error: " + d.string() + "/", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(": the set's name \""), std::string::npos) << r.output;
    EXPECT_EQ(snapshot_files(d), before);
  }
  fs::remove_all(d);
}

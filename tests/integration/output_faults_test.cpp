// Issue 26, the output side: faults while writing (full disk, read-only folder, kills and signals
// between renames, two writers into one -o) and hostile reports given to `preview`. Each test makes
// its own fault: a full disk is a file-size limit (ulimit -f, SIGXFSZ ignored, so write() fails
// with EFBIG as on a full disk), a read-only folder a read-only tmpfs (skipped where mounting is
// not allowed), kills the AHDPACK_TEST_KILL_BEFORE_RENAME hook of files/output_set.h.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "cli_runner.h"
#include "image/ahd_intermediate.h"
#include "files/manifest_file.h"
#include "files/output_set.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "file_bytes.h"

namespace fs = std::filesystem;
using namespace ahd;
using ahd_test::run_cli;

namespace {

void spit(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

// Every file of a folder (not hidden ones' contents: their names are compared).
std::map<std::string, std::string> snapshot_entries(const fs::path& d) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(d)) m[e.path().filename().string()] = e.is_regular_file() ? ahd_test::read_text(e.path()) : "<dir>";
  return m;
}

size_t hidden_in(const fs::path& d) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(d)) n += e.path().filename().string()[0] == '.';
  return n;
}

std::string sh_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs ahdpack under a file-size limit of `kib` KiB with SIGXFSZ ignored: every write past the
// limit fails with EFBIG, which is what a full disk looks like to a writer (ENOSPC).
ahd_test::CliResult run_full_disk(size_t kib, const std::vector<std::string>& args) {
  std::string cmd = "ulimit -f " + std::to_string(kib) + "; trap '' XFSZ; exec " + sh_quote(AHD_CLI_PATH);
  for (const auto& a : args) cmd += " " + sh_quote(a);
  ahd_test::CliResult r;
  const std::string out = ahd_test::run_shell("bash -c " + sh_quote(cmd) + " 2>&1; echo \"rc=$?\"");
  const size_t at = out.rfind("rc=");
  r.output = out.substr(0, at);
  r.exit_code = std::stoi(out.substr(at + 3));
  return r;
}

void expect_one_error_line(const ahd_test::CliResult& r, const std::string& file) {
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("ahdpack: error: " + file + ": ", 0), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

ahd_test::CliResult convert_room(const fs::path& out, const std::string& profile, int seed, bool keep = false) {
  std::vector<std::string> a = {"convert", "-o", out.string(), "--sample-size", "16", "--profile", profile,
                                "--seed", std::to_string(seed), "-q"};
  if (keep) a.push_back("--keep-intermediate");
  return run_cli(a);
}

// A set as `decode` reads it: every plane the manifest names present with its size and SHA-256.
::testing::AssertionResult complete_set(const fs::path& manifest) {
  try {
    const Manifest m = read_manifest_file(manifest.string());
    std::vector<Plane> planes;
    for (const auto& mp : m.planes) planes.push_back({mp.name, read_manifest_plane(manifest.string(), mp)});
    decode_planes(planes, m.ratio_form == RatioForm::Rgb, 0);
    return ::testing::AssertionSuccess();
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << e.what();
  }
}

// The files a clean folder holds for set `name`: manifest, report, planes (and the intermediate).
std::set<std::string> fault_set_files(const fs::path& dir, const std::string& name, bool intermediate = false) {
  std::set<std::string> s = {name + ".json", name + ".report.json"};
  if (intermediate) s.insert(name + ".ahd.exr");
  for (const auto& p : read_manifest_file((dir / (name + ".json")).string()).planes) s.insert(p.file);
  return s;
}

// What an intermediate holds (level 0's SH), not its bytes: OpenEXR stamps the write time.
std::vector<float> intermediate_sh(const fs::path& p) {
  try {
    return read_intermediate(p.string(), nullptr).at(0).sh.data;
  } catch (const std::exception&) {
    return {};
  }
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(ahd_test::read_text(p), nullptr, false); }

// A folder whose tmpfs is mounted read-only (unmounted by the destructor); empty path when this
// machine does not allow mounting (not root, a container without CAP_SYS_ADMIN).
struct ReadOnlyFolder {
  fs::path path;
  explicit ReadOnlyFolder(const fs::path& p) {
    fs::create_directories(p);
    if (::mount("none", p.c_str(), "tmpfs", MS_RDONLY, "size=64k") == 0) path = p;
  }
  ~ReadOnlyFolder() {
    if (!path.empty()) ::umount(path.c_str());
  }
};

}  // namespace

// Defect 6: `compress` on a full disk exited 0 and left a short file in place of the good one.
TEST(OutputFaults, CompressOnAFullDiskFailsAndKeepsThePreviousFile) {
  const fs::path d = ahd_test::temp_dir("faults_compress");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "s" / "room.ktx2").string(), "--sample-size", "16", "-q"}).exit_code, 0);
  ASSERT_EQ(run_cli({"decode", (d / "s" / "room.json").string(), "-o", (d / "in.exr").string()}).exit_code, 0);
  const fs::path out = d / "c.ktx2";
  ASSERT_EQ(run_cli({"compress", (d / "in.exr").string(), "-o", out.string()}).exit_code, 0);
  ASSERT_GT(ahd_test::read_text(out).size(), 256u);
  const auto before = snapshot_entries(d);
  // No room at all: the file is created, its buffered bytes fail at close (unchecked: 0 bytes, exit 0).
  const auto r = run_full_disk(0, {"compress", (d / "in.exr").string(), "-o", out.string(), "--quality", "fast"});
  expect_one_error_line(r, out.string());
  EXPECT_EQ(snapshot_entries(d), before);  // the previous file byte for byte, no temporary left
  fs::remove_all(d);
}

// Defect 6: `decode` on a full disk exited 0 and left a 1 KiB EXR in place of the good one.
TEST(OutputFaults, DecodeOnAFullDiskFailsAndKeepsThePreviousFile) {
  const fs::path d = ahd_test::temp_dir("faults_decode");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "s" / "room.ktx2").string(), "--sample-size", "16", "-q"}).exit_code, 0);
  const fs::path out = d / "irr.exr";
  ASSERT_EQ(run_cli({"decode", (d / "s" / "room.json").string(), "-o", out.string(), "--level", "1"}).exit_code, 0);
  const auto before = snapshot_entries(d);
  // 1 KiB of room: OpenEXR's last bytes fail at close, which was unchecked (a 1 KiB file, exit 0).
  const auto r = run_full_disk(1, {"decode", (d / "s" / "room.json").string(), "-o", out.string()});
  expect_one_error_line(r, out.string());
  EXPECT_EQ(snapshot_entries(d), before);
  fs::remove_all(d);
}

// Defect 6 for `decompress`, the other single-file writer of an image.
TEST(OutputFaults, DecompressOnAFullDiskFailsAndKeepsThePreviousFile) {
  const fs::path d = ahd_test::temp_dir("faults_decompress");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "s" / "room.ktx2").string(), "--sample-size", "16", "-q"}).exit_code, 0);
  ASSERT_EQ(run_cli({"decode", (d / "s" / "room.json").string(), "-o", (d / "in.exr").string()}).exit_code, 0);
  ASSERT_EQ(run_cli({"compress", (d / "in.exr").string(), "-o", (d / "c.ktx2").string()}).exit_code, 0);
  const fs::path out = d / "back.exr";
  ASSERT_EQ(run_cli({"decompress", (d / "c.ktx2").string(), "-o", out.string()}).exit_code, 0);
  const auto before = snapshot_entries(d);
  const auto r = run_full_disk(1, {"decompress", (d / "c.ktx2").string(), "-o", out.string()});
  expect_one_error_line(r, out.string());
  EXPECT_EQ(snapshot_entries(d), before);
  fs::remove_all(d);
}

// Defect 7: with --keep-intermediate, a conversion that failed after the fit had already replaced
// NAME.ahd.exr; on a full disk it became a short file. Now the intermediate is published with the
// set or not at all: the folder is byte for byte the previous one.
TEST(OutputFaults, KeepIntermediateFailedConversionKeepsThePreviousIntermediate) {
  const fs::path d = ahd_test::temp_dir("faults_keep");
  ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0, true).exit_code, 0);
  ASSERT_TRUE(fs::exists(d / "room.ahd.exr"));
  const auto before = snapshot_entries(d);
  // A plane's write fails (the fit, and so the intermediate, already done; seed 1: other bytes).
  ::setenv("AHDPACK_TEST_WRITE_FAULT", "0:ENOSPC", 1);
  const auto r = convert_room(d / "room.ktx2", "uncompressed", 1, true);
  ::unsetenv("AHDPACK_TEST_WRITE_FAULT");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(snapshot_entries(d), before);
  // A full disk: 24 KiB holds every plane of 16x16 but not the intermediate.
  const auto full = run_full_disk(24, {"convert", "-o", (d / "room.ktx2").string(), "--sample-size", "16", "--seed", "1",
                                       "--keep-intermediate", "-q"});
  expect_one_error_line(full, (d / "room.ahd.exr").string());
  EXPECT_EQ(snapshot_entries(d), before);
  EXPECT_TRUE(complete_set(d / "room.json"));
  fs::remove_all(d);
}

// Weaker item: converting without --keep-intermediate left the previous NAME.ahd.exr, so transcode
// re-emitted an older conversion. It goes with the set it belonged to; transcoding NAME.ahd.exr into
// NAME itself keeps it (same fit).
TEST(OutputFaults, ConversionWithoutKeepIntermediateRemovesTheOldIntermediate) {
  const fs::path d = ahd_test::temp_dir("faults_old_intermediate");
  ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0, true).exit_code, 0);
  const auto t = run_cli({"transcode", (d / "room.ahd.exr").string(), "-o", (d / "room.ktx2").string(), "--profile", "pc-bc", "-q"});
  ASSERT_EQ(t.exit_code, 0) << t.output;
  EXPECT_TRUE(fs::exists(d / "room.ahd.exr"));
  EXPECT_EQ(ahd_test::names_in(d), fault_set_files(d, "room", true));
  ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 1).exit_code, 0);
  EXPECT_FALSE(fs::exists(d / "room.ahd.exr"));
  EXPECT_EQ(ahd_test::names_in(d), fault_set_files(d, "room"));
  fs::remove_all(d);
}

// Defect 8: a kill just before the manifest's rename left the old manifest beside the new run's
// report. Killed before every rename in turn (and after the last), the folder holds one manifest
// whose planes are all there, and every report and intermediate in it belongs to that manifest
// (or is missing); the next run leaves exactly its set.
TEST(OutputFaults, KilledAtEveryRenameLeavesAnnexesOfTheManifestOnly) {
  const fs::path root = ahd_test::temp_dir("faults_kill");
  const fs::path ref_old = root / "ref_old", ref_new = root / "ref_new";
  ASSERT_EQ(convert_room(ref_old / "room.ktx2", "uncompressed", 0, true).exit_code, 0);
  ASSERT_EQ(convert_room(ref_new / "room.ktx2", "pc-bc", 1, true).exit_code, 0);
  const std::string old_manifest = ahd_test::read_text(ref_old / "room.json"), new_manifest = ahd_test::read_text(ref_new / "room.json");
  const std::vector<float> old_im = intermediate_sh(ref_old / "room.ahd.exr"), new_im = intermediate_sh(ref_new / "room.ahd.exr");
  ASSERT_FALSE(old_im.empty());
  ASSERT_TRUE(old_im != new_im);
  size_t saw_old = 0, saw_new = 0;
  for (int k = 0;; ++k) {
    ASSERT_LT(k, 30) << "the hook never stopped killing";
    SCOPED_TRACE("killed before rename " + std::to_string(k));
    const fs::path d = root / ("k" + std::to_string(k));
    ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0, true).exit_code, 0);
    ::setenv("AHDPACK_TEST_KILL_BEFORE_RENAME", std::to_string(k).c_str(), 1);
    const auto killed = convert_room(d / "room.ktx2", "pc-bc", 1, true);
    ::unsetenv("AHDPACK_TEST_KILL_BEFORE_RENAME");
    const bool done = killed.exit_code == 0;
    const std::string now = ahd_test::read_text(d / "room.json");
    const bool is_old = now == old_manifest;
    ASSERT_TRUE(is_old || now == new_manifest);
    saw_old += is_old;
    saw_new += !is_old;
    EXPECT_TRUE(complete_set(d / "room.json"));
    if (fs::exists(d / "room.report.json"))
      EXPECT_EQ(read_json(d / "room.report.json").value("profile", ""), is_old ? "uncompressed" : "pc-bc");
    if (fs::exists(d / "room.ahd.exr")) EXPECT_TRUE(intermediate_sh(d / "room.ahd.exr") == (is_old ? old_im : new_im));
    ASSERT_EQ(convert_room(d / "room.ktx2", "pc-bc", 1, true).exit_code, 0);
    EXPECT_EQ(ahd_test::names_in(d), fault_set_files(d, "room", true));
    EXPECT_EQ(ahd_test::read_text(d / "room.json"), new_manifest);
    EXPECT_TRUE(intermediate_sh(d / "room.ahd.exr") == new_im);
    if (done) break;  // k passed the last rename and the clean-up
  }
  EXPECT_GT(saw_old, 0u);
  EXPECT_GT(saw_new, 0u);
  fs::remove_all(root);
}

// Weaker item: SIGINT (and SIGTERM) between two renames left a renamed plane of the uncommitted
// set behind. Now the signal undoes the publish: before the commit the folder is the previous set
// exactly; after it, the new set (its annexes may be missing) with nothing else.
TEST(OutputFaults, SignalBetweenRenamesLeavesNoOrphan) {
  const fs::path root = ahd_test::temp_dir("faults_sigint");
  for (const char* sig : {"INT", "TERM"}) {
    for (int k = 0;; ++k) {
      ASSERT_LT(k, 30);
      SCOPED_TRACE(std::string(sig) + " before rename " + std::to_string(k));
      const fs::path d = root / (sig + std::to_string(k));
      ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0).exit_code, 0);
      const auto before = snapshot_entries(d);
      const std::set<std::string> old_set = fault_set_files(d, "room");
      ::setenv("AHDPACK_TEST_KILL_BEFORE_RENAME", (std::to_string(k) + ":" + sig).c_str(), 1);
      const auto r = convert_room(d / "room.ktx2", "pc-bc", 1);
      ::unsetenv("AHDPACK_TEST_KILL_BEFORE_RENAME");
      if (r.exit_code == 0) {
        EXPECT_GT(k, 3) << "the signal hook did not fire";
        break;
      }
      const int signo = std::string(sig) == "INT" ? SIGINT : SIGTERM;
      EXPECT_TRUE(r.exit_code == 128 + signo || r.exit_code == -1) << "not killed by the signal: " << r.output;
      EXPECT_TRUE(complete_set(d / "room.json"));
      if (read_json(d / "room.json").value("profile", "") == "uncompressed") {
        EXPECT_EQ(snapshot_entries(d), before);
      } else {
        std::set<std::string> now = ahd_test::names_in(d), want = fault_set_files(d, "room");
        if (!now.count("room.report.json")) want.erase("room.report.json");
        EXPECT_EQ(now, want);
      }
    }
  }
  fs::remove_all(root);
}

// Defect 9: two conversions into one -o at once both exited 0, but in 77 of 150 pairs the
// manifest named a plane the other run had deleted. The folder lock of files/output_set.h makes them
// take turns: after each of 100 pairs (different profiles and seeds, so different plane files),
// the folder holds one complete set, its report of the same run, and nothing else.
TEST(OutputFaults, HundredPairsOfConcurrentConversionsLeaveOneCompleteSet) {
  const fs::path d = ahd_test::temp_dir("faults_concurrent");
  const std::string out = sh_quote((d / "room.ktx2").string()), cli = sh_quote(AHD_CLI_PATH);
  size_t broken = 0;
  for (int i = 0; i < 100; ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    const std::string a = cli + " convert -o " + out + " --sample-size 8 -q --profile uncompressed --seed " + std::to_string(2 * i);
    const std::string b = cli + " convert -o " + out + " --sample-size 8 -q --profile pc-bc --seed " + std::to_string(2 * i + 1);
    const std::string rc = ahd_test::run_shell("(" + a + ") & A=$!; (" + b + ") & B=$!; wait $A; ra=$?; wait $B; echo \"$ra $?\"");
    ASSERT_EQ(rc, "0 0\n");
    const bool ok = complete_set(d / "room.json") && ahd_test::names_in(d) == fault_set_files(d, "room") &&
                    read_json(d / "room.report.json").value("profile", "") ==
                        read_json(d / "room.json").value("profile", "?");
    broken += !ok;
  }
  EXPECT_EQ(broken, 0u);
  EXPECT_TRUE(complete_set(d / "room.json"));
  fs::remove_all(d);
}

// Defect 11: a deeply nested report overflowed the stack in preview (and left its hidden temporary
// folder). Now one error line naming the report, exit 1, no output and no temporary folder.
TEST(OutputFaults, PreviewOfADeeplyNestedReportIsOneErrorLine) {
  const fs::path d = ahd_test::temp_dir("faults_deep");
  ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0).exit_code, 0);
  spit(d / "room.report.json", "{\"x\":" + std::string(200000, '[') + std::string(200000, ']') + "}");
  const auto r = run_cli({"preview", (d / "room.json").string(), "-o", (d / "page").string()});
  expect_one_error_line(r, (d / "room.report.json").string());
  EXPECT_FALSE(fs::exists(d / "page"));
  EXPECT_EQ(hidden_in(d), 0u);
  // At the bound, a report still previews.
  spit(d / "room.report.json", "{\"x\":" + std::string(63, '[') + std::string(63, ']') + "}");
  EXPECT_EQ(run_cli({"preview", (d / "room.json").string(), "-o", (d / "page").string()}).exit_code, 0);
  fs::remove_all(d);
}

// Defect 12: report values reached the page unescaped, so a crafted report ran script. Every
// string of a real report (keys and values, at every depth, numbers turned into strings too) is
// replaced by markup; the page has its own one <script> and none of the markup.
TEST(OutputFaults, PreviewEscapesEveryReportValue) {
  const fs::path d = ahd_test::temp_dir("faults_escape");
  ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0).exit_code, 0);
  const std::string evil = "<script>alert(1)</script>\"'</textarea><img src=x onerror=alert(2)>&";
  std::function<nlohmann::json(const nlohmann::json&)> craft = [&](const nlohmann::json& j) -> nlohmann::json {
    if (j.is_object()) {
      nlohmann::json o = nlohmann::json::object();
      for (auto it = j.begin(); it != j.end(); ++it) o[it.key()] = craft(*it), o[evil + it.key()] = craft(*it);
      return o;
    }
    if (j.is_array()) {
      nlohmann::json a = nlohmann::json::array();
      for (const auto& e : j) a.push_back(craft(e));
      return a;
    }
    return evil;
  };
  const nlohmann::json report = read_json(d / "room.report.json");
  ASSERT_TRUE(report.is_object());
  spit(d / "room.report.json", craft(report).dump());
  const auto r = run_cli({"preview", (d / "room.json").string(), "-o", (d / "page").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = ahd_test::read_text(d / "page" / "index.html");
  size_t scripts = 0;
  for (size_t at = html.find("<script"); at != std::string::npos; at = html.find("<script", at + 1)) ++scripts;
  EXPECT_EQ(scripts, 1u);
  EXPECT_EQ(html.find("</textarea"), std::string::npos);
  EXPECT_EQ(html.find("<img src=x"), std::string::npos);
  EXPECT_EQ(html.find("'</"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt;&quot;&#39;&lt;/textarea&gt;"), std::string::npos);
  fs::remove_all(d);
}

// Weaker item: Ctrl-C during `preview` left its hidden temporary folder. SIGINT at a spread of
// moments during the preview of a larger conversion: afterwards the page is complete or absent and
// no hidden folder is left (whenever the signal lands; nothing here depends on timing to pass).
TEST(OutputFaults, InterruptedPreviewLeavesNoTemporaryFolder) {
  const fs::path d = ahd_test::temp_dir("faults_preview_int");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "s" / "room.ktx2").string(), "--sample-size", "256", "-q"}).exit_code, 0);
  const std::string cmd = sh_quote(AHD_CLI_PATH) + " preview " + sh_quote((d / "s" / "room.json").string()) + " -o " +
                          sh_quote((d / "page").string()) + " >/dev/null 2>&1";
  size_t interrupted = 0;
  // `set -m`: without job control a shell starts background commands with SIGINT ignored, so a
  // signal landing before ahdpack installs its handler would be lost and the run never interrupted.
  for (const char* delay : {"0.1", "0.2", "0.3", "0.4", "0.5", "0.7", "1", "1.5"}) {
    SCOPED_TRACE(delay);
    fs::remove_all(d / "page");
    const std::string rc = ahd_test::run_shell("set -m; " + cmd + " & P=$!; sleep " + delay + "; kill -INT $P; wait $P; echo $?");
    EXPECT_TRUE(rc == "130\n" || rc == "0\n") << rc;
    interrupted += rc == "130\n";
    EXPECT_EQ(hidden_in(d), 0u);
    if (fs::exists(d / "page")) EXPECT_TRUE(fs::exists(d / "page" / "index.html"));
  }
  EXPECT_GT(interrupted, 0u) << "every preview finished before its signal: nothing was tested";
  fs::remove_all(d);
}

// Weaker item: a read-only output folder gave "internal error … cannot remove" and exit 2. Every
// writer now says one line naming its output, exit 1.
TEST(OutputFaults, ReadOnlyFolderIsOneErrorLineForEveryWriter) {
  const fs::path d = ahd_test::temp_dir("faults_ro");
  ASSERT_EQ(convert_room(d / "s" / "room.ktx2", "uncompressed", 0, true).exit_code, 0);
  ASSERT_EQ(run_cli({"decode", (d / "s" / "room.json").string(), "-o", (d / "in.exr").string()}).exit_code, 0);
  std::unique_ptr<ReadOnlyFolder> ro_folder = std::make_unique<ReadOnlyFolder>(d / "ro");
  const ReadOnlyFolder& ro = *ro_folder;
  if (ro.path.empty()) GTEST_SKIP() << "cannot mount a read-only tmpfs here (needs root)";
  const std::string o = ro.path.string();
  struct Case {
    std::vector<std::string> args;
    std::string named;
  } cases[] = {
      {{"decode", (d / "s" / "room.json").string(), "-o", o + "/x.exr"}, o + "/x.exr"},
      {{"compress", (d / "in.exr").string(), "-o", o + "/c.ktx2"}, o + "/c.ktx2"},
      {{"convert", "-o", o + "/room.ktx2", "--sample-size", "16", "-q", "--keep-intermediate"}, o + "/room."},
      {{"transcode", (d / "s" / "room.ahd.exr").string(), "-o", o + "/t.ktx2", "-q"}, o + "/t."},
      {{"preview", (d / "s" / "room.json").string(), "-o", o + "/p"}, o + "/p"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args[0]);
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.rfind("ahdpack: error: " + c.named, 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  ro_folder.reset();  // unmounted
  fs::remove_all(d);
}

// Weaker item: batch `-o out.ktx2` silently made a folder out.ktx2/.
TEST(OutputFaults, BatchIntoAFileNameIsRefused) {
  const fs::path d = ahd_test::temp_dir("faults_batch_name");
  ASSERT_EQ(run_cli({"sample", "--size", "8", "-o", (d / "a.exr").string()}).exit_code, 0);
  ASSERT_EQ(run_cli({"sample", "--size", "8", "-o", (d / "b.exr").string()}).exit_code, 0);
  const auto r = run_cli({"convert", (d / "a.exr").string(), (d / "b.exr").string(), "-o", (d / "out.ktx2").string(), "-q"});
  expect_one_error_line(r, (d / "out.ktx2").string());
  EXPECT_FALSE(fs::exists(d / "out.ktx2"));
  fs::remove_all(d);
}

// Weaker item: `-o .room.ktx2` or `-o a:b.ktx2` wrote sets that `decode` refuses. The set's name is
// checked with decode's own rule (manifest.h is_plain_file_name) before anything is written.
TEST(OutputFaults, SetNamesDecodeWouldRefuseAreRefusedUpFront) {
  const fs::path d = ahd_test::temp_dir("faults_set_name");
  for (const char* name : {".room.ktx2", "a:b.ktx2", "x\\y.dds"}) {
    SCOPED_TRACE(name);
    const auto r = run_cli({"convert", "-o", (d / name).string(), "--sample-size", "8", "-q"});
    expect_one_error_line(r, (d / name).string());
    EXPECT_TRUE(fs::is_empty(d));
  }
  fs::remove_all(d);
}

// Weaker item: convert deleted a user's own room.iz.dds or room.coverage.ktx2 because they matched
// the plane naming. Plane clean-up removes the files the previous manifest names, and unnamed plane
// files only when their content hash is the one in their name (ahdpack's, left by a killed run).
TEST(OutputFaults, PlaneCleanUpKeepsTheUsersOwnFiles) {
  const fs::path d = ahd_test::temp_dir("faults_users_files");
  ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0).exit_code, 0);
  const std::map<std::string, std::string> mine = {{"room.iz.dds", "mine 1"},
                                                   {"room.coverage.ktx2", "mine 2"},
                                                   {"room.dir.0123456789ab.ktx2", "mine 3 (a hash that is not its own)"}};
  for (const auto& [f, text] : mine) spit(d / f, text);
  // An orphan plane of a killed run: a real plane file under its own content-addressed name.
  const std::string orphan = fs::path(ahd_test::plane_file((d / "room.json").string(), "iz")).filename().string();
  ASSERT_EQ(convert_room(d / "room.ktx2", "pc-bc", 1).exit_code, 0);
  for (const auto& [f, text] : mine) EXPECT_EQ(ahd_test::read_text(d / f), text) << f;
  ASSERT_FALSE(fs::exists(d / orphan));  // the first set's plane went with its manifest
  ASSERT_EQ(convert_room(d / "room.ktx2", "uncompressed", 0).exit_code, 0);  // brings it back
  ASSERT_TRUE(fs::exists(d / orphan));
  fs::copy_file(d / orphan, d / "keep.tmp");
  ASSERT_EQ(convert_room(d / "room.ktx2", "pc-bc", 1).exit_code, 0);
  fs::rename(d / "keep.tmp", d / orphan);  // as a killed run would leave it: unnamed by the manifest
  ASSERT_EQ(convert_room(d / "room.ktx2", "pc-bc", 1).exit_code, 0);
  EXPECT_FALSE(fs::exists(d / orphan));
  std::set<std::string> want = fault_set_files(d, "room");
  for (const auto& [f, text] : mine) want.insert(f);
  EXPECT_EQ(ahd_test::names_in(d), want);
  fs::remove_all(d);
}

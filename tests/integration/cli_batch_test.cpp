// `ahdpack convert IN1 IN2 … -o OUTDIR/`: how a batch shares the machine (small files side by side
// with one thread each, large ones alone with every thread) never changes a byte of any output,
// and what it prints stays ordered and readable. (Past-failure behaviour: cli_test.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "cli/batch_schedule.h"
#include "cli_runner.h"
#include "image/sh_exr.h"
#include "sample/analytic_baker.h"
#include "cli_batch_fixture.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

using namespace ahd_fixture::cli_batch_fixture;


// Several small files (L1 and L2, different scenes and sizes) and one just past the small limit,
// batched on two threads: the small ones go two at a time with one thread each, the large one
// alone; every output file is byte-identical to the same file converted alone with every thread,
// and the summary lists the files in input order.
TEST(Cli, BatchOfSmallFilesSideBySideWritesTheBytesOfEachConvertedAlone) {
  const fs::path d = ahd_test::temp_dir("cli_batch_bytes");
  std::vector<std::string> names;
  for (int i = 0; i < 5; ++i) {
    ahd::BakerOptions bo;
    bo.width = 24 + 8 * i;
    bo.height = 32;
    bo.coeffs = i % 2 ? 4 : 9;
    bo.seed = uint32_t(i);
    bo.area_samples = 2;
    names.push_back("s" + std::to_string(i));
    ahd::write_canonical_sh((d / (names.back() + ".exr")).string(), ahd::bake_analytic_scene(bo));
  }
  {  // one texel row past 512²: a large file
    ahd::BakerOptions bo;
    bo.width = 1024;
    bo.height = int(ahd::cli::kSmallBatchTexels / 1024) + 1;
    bo.area_samples = 1;
    names.push_back("big");
    ahd::write_canonical_sh((d / "big.exr").string(), ahd::bake_analytic_scene(bo));
  }
  std::vector<std::string> args = {"convert"};
  for (const std::string& n : names) args.push_back((d / (n + ".exr")).string());
  for (const char* a : {"-o", "", "--profile", "pc-bc", "--threads", "2"}) args.push_back(a);
  args[args.size() - 5] = (d / "batch").string() + "/";
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("6 file(s) in "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("5 small (at most 512x512 texels) 2 at a time with 1 thread each, 1 larger (or unread) one at a time with 2 threads"),
            std::string::npos)
      << r.output;
  size_t last = 0;  // the table, in input order
  for (const std::string& n : names) {
    const size_t at = r.output.find(n + ".exr ");
    ASSERT_NE(at, std::string::npos) << n << "\n" << r.output;
    EXPECT_GT(at, last) << n << "\n" << r.output;
    last = at;
  }

  std::map<std::string, std::string> alone;
  for (const std::string& n : names) {
    const auto one = run_cli({"convert", (d / (n + ".exr")).string(), "-o", (d / "alone" / (n + ".ktx2")).string(),
                              "--profile", "pc-bc", "-q"});
    ASSERT_EQ(one.exit_code, 0) << one.output;
    EXPECT_TRUE(fs::exists(d / "batch" / (n + ".report.json"))) << n;
  }
  const auto batch = outputs_in(d / "batch"), single = outputs_in(d / "alone");
  EXPECT_EQ(batch.size(), names.size() * 4);  // manifest + iz, dir, ratio planes
  ASSERT_EQ(batch.size(), single.size());
  for (const auto& [name, bytes] : single) {
    const auto it = batch.find(name);
    ASSERT_NE(it, batch.end()) << name << " converted alone is missing from the batch";
    EXPECT_TRUE(it->second == bytes) << name << " differs between the batch and the file converted alone";
  }
  fs::remove_all(d);
}

// On a terminal a batch shows one line, "files k/N done", redrawn in place — no per-stage line of
// the files running side by side; a file converted alone adds its stage. Nothing of it in a pipe.
TEST(Cli, BatchProgressIsOneLineOnATerminalOnly) {
  const fs::path d = ahd_test::temp_dir("cli_batch_tty");
  ahd::BakerOptions bo;
  bo.width = bo.height = 16;
  bo.area_samples = 2;
  ahd::write_canonical_sh((d / "a.exr").string(), ahd::bake_analytic_scene(bo));
  bo.seed = 2;
  ahd::write_canonical_sh((d / "b.exr").string(), ahd::bake_analytic_scene(bo));
  const std::string batch = std::string("'") + AHD_CLI_PATH + "' convert '" + (d / "a.exr").string() + "' '" +
                            (d / "b.exr").string() + "' -o '" + (d / "out").string() + "/' --threads ";
  const std::string convert = batch + "2";
  const std::string tty = ahd_test::run_shell("script -qec \"" + convert + "\" /dev/null 2>&1");
  EXPECT_NE(tty.find("\r\033[Kfiles 2/2 done"), std::string::npos) << tty;
  EXPECT_EQ(tty.find("encode"), std::string::npos) << tty;  // no stage of files side by side
  EXPECT_NE(tty.find("2 at a time"), std::string::npos) << tty;
  const std::string alone = ahd_test::run_shell("script -qec \"" + batch + "1\" /dev/null 2>&1");
  EXPECT_NE(alone.find("a.exr: write 100 %"), std::string::npos) << alone;
  EXPECT_NE(alone.find("one at a time"), std::string::npos) << alone;
  const std::string piped = ahd_test::run_shell(convert + " 2>&1 | cat");
  EXPECT_EQ(piped.find("\r\033[K"), std::string::npos) << piped;
  EXPECT_EQ(piped.find("files "), std::string::npos) << piped;
  EXPECT_NE(piped.find("2 file(s) in"), std::string::npos) << piped;  // the summary still prints
  const std::string quiet = ahd_test::run_shell("script -qec \"" + convert + " -q\" /dev/null 2>&1");
  EXPECT_TRUE(quiet.empty()) << quiet;
  fs::remove_all(d);
}

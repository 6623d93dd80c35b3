// CpuDisableHook.*: the CLI's test hook AHD_CPU_DISABLE (src/cli/environment.h), which
// scripts/platform-cli-bytes.sh uses to run the CLI down each SIMD path: a malformed mask is an
// error, and a conversion down the plain scalar loops writes the bytes of the default run.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "file_bytes.h"

namespace fs = std::filesystem;

TEST(CpuDisableHook, MalformedMaskIsAnError) {
  for (const char* bad : {"abc", "-1", "32", "8x", "99999999999999999999"}) {
    const std::string out = ahd_test::run_shell(std::string("AHD_CPU_DISABLE='") + bad + "' '" + AHD_CLI_PATH +
                                                "' layouts 2>&1; echo \"rc=$?\"");
    EXPECT_NE(out.find("AHD_CPU_DISABLE is '"), std::string::npos) << bad << ": " << out;
    EXPECT_NE(out.find("rc=1"), std::string::npos) << bad << ": " << out;
  }
  const std::string ok = ahd_test::run_shell(std::string("AHD_CPU_DISABLE=31 '") + AHD_CLI_PATH +
                                             "' layouts >/dev/null 2>&1; echo \"rc=$?\"");
  EXPECT_NE(ok.find("rc=0"), std::string::npos) << ok;
}

TEST(CpuDisableHook, ScalarPathWritesTheDefaultBytes) {
  const fs::path d = ahd_test::temp_dir("cpu_disable_hook");
  for (const char* mask : {"", "31"}) {
    const fs::path out = d / (std::string("m") + mask);
    fs::create_directories(out);
    const std::string r = ahd_test::run_shell(std::string("AHD_CPU_DISABLE=") + mask + " '" + AHD_CLI_PATH +
                                              "' convert -o '" + (out / "s.ktx2").string() +
                                              "' --sample-size 64 --profile pc-bc -q 2>&1; echo \"rc=$?\"");
    ASSERT_NE(r.find("rc=0"), std::string::npos) << mask << ": " << r;
    fs::remove(out / "s.report.json");  // it holds seconds
  }
  const auto names = ahd_test::names_in(d / "m");
  EXPECT_EQ(names, ahd_test::names_in(d / "m31"));  // the planes' names carry their hashes
  EXPECT_GE(names.size(), 4u);
  for (const std::string& n : names) EXPECT_EQ(ahd_test::slurp(d / "m" / n), ahd_test::slurp(d / "m31" / n)) << n;
  fs::remove_all(d);
}

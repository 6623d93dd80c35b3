// ahdpack bench convert, run as a command: a tiny generated run and a real plain file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "image/image_io.h"
#include "files/profile_file.h"
#include "cli_runner.h"
#include "fit/hemisphere_error.h"
#include "pipeline/convert.h"
#include "pipeline/profile.h"
#include "sample/analytic_baker.h"
#include "error_estimate_fixture.h"

using namespace ahd;
using namespace ahd_fixture::error_estimate_fixture;


TEST(BenchConvert, TinyRunPrintsTimesAndMemory) {
  const auto r = ahd_test::run_cli({"bench", "convert", "--sizes", "16", "--plain", "16", "--threads", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("L2 16²"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("plain 16²"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("peak MB"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stages: read"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("OIIO read alone"), std::string::npos) << r.output;
  // Each input also converted by `ahdpack convert` processes, their start included.
  EXPECT_NE(r.output.find("whole process (`ahdpack convert`, its start included; median of 5): CPU"), std::string::npos)
      << r.output;
}

TEST(BenchConvert, RealPlainFileRunsBesideTheGeneratedOnes) {
  // --plain-file: a given plain RGB EXR (a real bake in use; here a 20×12 one with a black
  // gutter column, not square) converted with the plain layout; --sizes 0 --plain 0: nothing else.
  const std::string dir = ahd_test::temp_dir("bench_plain_file");
  ImageF img(20, 12, 3);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 20; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y)[c] = x == 9 ? 0.0f : 0.05f * float(1 + x + y + c);
  write_image(dir + "/bake_plain.exr", img, true, {"R", "G", "B"});
  const auto r = ahd_test::run_cli(
      {"bench", "convert", "--sizes", "0", "--plain", "0", "--plain-file", dir + "/bake_plain.exr", "--threads", "1",
       "--process-runs", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("bake_plain"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("    0.00 "), std::string::npos) << r.output;  // 240 texels: 0.00 MTexels
  EXPECT_EQ(r.output.find("L2 "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("plain 2048"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("whole process"), std::string::npos) << r.output;  // --process-runs 0
  const auto bad = ahd_test::run_cli({"bench", "convert", "--plain-file", dir + "/missing.exr"});
  EXPECT_NE(bad.exit_code, 0);
}

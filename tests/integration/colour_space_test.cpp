// Colour spaces through the command and against the numpy reference (tests/colour_reference.py).
// In-process tests: tests/unit/colour_space_test.cpp.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_runner.h"
#include "bakers/baker_layout.h"
#include "image/colour_space.h"
#include "image/sh_exr.h"
#include "colour_space_fixture.h"

namespace ahd {
using namespace ahd_fixture::colour_space_fixture;

// OpenColorIO's matrix for every named space equals the numpy derivation (its builtin Bradford
// transforms for the ACES spaces, our chromaticity matrix for Rec.2020 and P3-D65).
TEST(ColourSpace, NumpyReferenceMatchesEverySpace) {
  for (const std::string space : {"acescg", "aces2065-1", "rec2020", "p3-d65"}) {
    const std::vector<double> ref = numpy_matrix(space);
    REQUIRE_NUMPY(ref);
    const Matrix3 m = working_space_matrix(parse_input_space(space), "test");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(m[size_t(r)][size_t(c)], ref[size_t(r * 3 + c)], 1e-6) << space << " " << r << c;
  }
}

// The done-when line of issue 25: an EXR declaring ACEScg (AP1 chromaticities) converts, and every
// coefficient of every band equals the numpy matrix times the stored value, to 1e-5.
TEST(ColourSpace, NumpyAcesCgExrConvertsToTheReference) {
  const std::vector<double> ref = numpy_matrix("acescg");
  REQUIRE_NUMPY(ref);
  const std::string d = tmp("acescg");
  const ShImage sh = test_sh();
  write_sh_exr(d + "/acescg.exr", sh, kAp1);
  ReadStats rs;
  const ShImage got = read_canonical_sh(d + "/acescg.exr", &rs);
  expect_converted(sh, got, ref);
  EXPECT_NE(rs.input_space.find("ACEScg"), std::string::npos) << rs.input_space;
  // The same through a baker layout (the canonical preset reads the same file).
  expect_converted(sh, read_layout(load_layout("canonical"), d + "/acescg.exr", ""), ref);
}

// The command: the report records the space converted from, a non-convertible declaration is one
// error line and no output, and --input-space is part of the conversion's key.
TEST(ColourSpace, CliReportKeyAndRefusal) {
  const std::string d = tmp("cli");
  const ShImage sh = test_sh(8, 8);
  write_sh_exr(d + "/ap1.exr", sh, kAp1);
  write_sh_exr(d + "/none.exr", sh, {});
  write_sh_exr(d + "/flat.exr", sh, {0.3f, 0.3f, 0.4f, 0.4f, 0.5f, 0.5f, 0.3127f, 0.3290f});
  auto r = ahd_test::run_cli({"convert", d + "/ap1.exr", "-o", d + "/out/ap1.ktx2", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream rep(d + "/out/ap1.report.json");
  const std::string report((std::istreambuf_iterator<char>(rep)), std::istreambuf_iterator<char>());
  EXPECT_NE(report.find("\"input_space\": \"ACEScg"), std::string::npos) << report.substr(0, 400);

  r = ahd_test::run_cli({"convert", d + "/flat.exr", "-o", d + "/bad/flat.ktx2"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("flat.exr: declares degenerate chromaticities"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(d + "/bad") && !fs::is_empty(d + "/bad"));

  auto key = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = {"convert", d + "/none.exr", "-o", d + "/k/none.ktx2", "--print-key"};
    a.insert(a.end(), extra.begin(), extra.end());
    const auto k = ahd_test::run_cli(a);
    EXPECT_EQ(k.exit_code, 0) << k.output;
    return k.output;
  };
  const std::string plain = key({}), acescg = key({"--input-space", "acescg"});
  EXPECT_NE(plain, acescg);
  EXPECT_NE(acescg, key({"--input-space", "rec2020"}));
  EXPECT_EQ(plain, key({}));
  r = ahd_test::run_cli({"convert", d + "/none.exr", "-o", d + "/k/none.ktx2", "--input-space", "logc"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("unknown space 'logc'"), std::string::npos) << r.output;
}

}  // namespace ahd

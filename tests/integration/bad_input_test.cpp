// Issue 15's bad inputs through the command: a one-channel iz plane for decode, an image over the
// size limit. In-process cases: tests/unit/bad_input_test.cpp.
#include <gtest/gtest.h>
#include <zstd.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "files/manifest_file.h"
#include "files/container_file.h"
#include "files/profile_file.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "sanitized.h"
#include "containers/container.h"
#include "containers/dds.h"
#include "containers/ktx2.h"
#include "containers/limits.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "image/ahd_intermediate.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "scene/mesh_io.h"
#include "files/output_set.h"
#include "image/sh_exr.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "sample/analytic_baker.h"
#include "bad_input_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::bad_input_fixture;


namespace {

std::string run_sh(const std::string& cmd, int* status) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  std::string out;
  char buf[512];
  size_t n;
  while (p && (n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  *status = p ? pclose(p) : -1;
  return out;
}

}  // namespace

// Issue 15, case 1 through the CLI: a set whose iz plane is an R8 DDS, with a manifest saying so
// and hashes that match (a crafted set, not a corrupted one). `decode` used to exit 0 with an EXR
// of whatever memory followed the plane; now one line, exit 1, no EXR.
TEST(BadInput, CliDecodeRefusesOneChannelIzPlane) {
  const fs::path d = ahd_test::temp_dir("bad_iz_cli");
  const Manifest good = write_previous_set(d, "prev", "dds");
  Manifest m = good;
  const Texture r8 = plain_texture(PixelFormat::R8_UNORM, 8, 8, m.levels);
  const std::vector<uint8_t> bytes = write_dds(r8);
  spit(d / "r8.dds", bytes);
  m.planes[0].file = "r8.dds";
  m.planes[0].format = PixelFormat::R8_UNORM;
  m.planes[0].bytes = bytes.size();
  m.planes[0].sha256 = sha256_hex(bytes.data(), bytes.size());
  spit(d / "bad.json", manifest_to_json(m));
  const auto r = ahd_test::run_cli({"decode", (d / "bad.json").string(), "-o", (d / "e.exr").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output, "ahdpack: error: " + (d / "bad.json").string() + ": plane iz cannot be r8 (needs an HDR float format)\n");
  EXPECT_FALSE(fs::exists(d / "e.exr"));
  // The same with the dir plane as R8 (2 channels needed).
  m = good;
  m.planes[1].file = "r8.dds";
  m.planes[1].format = PixelFormat::R8_UNORM;
  m.planes[1].bytes = bytes.size();
  m.planes[1].sha256 = sha256_hex(bytes.data(), bytes.size());
  spit(d / "bad.json", manifest_to_json(m));
  const auto r2 = ahd_test::run_cli({"decode", (d / "bad.json").string(), "-o", (d / "e.exr").string()});
  EXPECT_EQ(r2.exit_code, 1) << r2.output;
  EXPECT_NE(r2.output.find("plane dir cannot be r8 (1 channel(s), needs 2)"), std::string::npos) << r2.output;
  EXPECT_FALSE(fs::exists(d / "e.exr"));
  fs::remove_all(d);
}

// Issue 15, case 5 through the CLI: a 100000x1 EXR is refused when read (naming the file and the
// limit), before any fitting, and nothing is written.
TEST(BadInput, CliRefusesOverLimitImageWhenRead) {
  const fs::path d = ahd_test::temp_dir("wide_cli");
  write_sh(d / "wide.exr", 100000, 1, 0.5f);
  const auto r = ahd_test::run_cli({"convert", (d / "wide.exr").string(), "-o", (d / "out" / "w.ktx2").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output, "ahdpack: error: " + (d / "wide.exr").string() +
                          ": 100000x1 is over the size limit of 16384x16384 texels per level (AHDPACK_MAX_SIZE raises it)\n");
  EXPECT_FALSE(fs::exists(d / "out"));
  // AHDPACK_MAX_SIZE lowers (or raises) the limit for a run.
  write_sh(d / "small.exr", 40, 8, 0.5f);
  int st = 0;
  const std::string out = run_sh("AHDPACK_MAX_SIZE=32 '" AHD_CLI_PATH "' convert '" + (d / "small.exr").string() + "' -o '" +
                                     (d / "out" / "s.ktx2").string() + "'",
                                 &st);
  EXPECT_EQ(WEXITSTATUS(st), 1) << out;
  EXPECT_NE(out.find("40x8 is over the size limit of 32x32"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

// Issue 44 (untrusted input and faults, round 3), the cook's side beyond the Cook/OutputSet/Api
// suites: where the OpenImageIO module is looked for.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "core/image.h"
#include "image/image_io.h"

namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

}  // namespace

// A relocated binary dlopen'ed libahd_oiio.so from its compiled-in build path, whatever that path
// holds now. The module is looked for relative to the running executable only: a copy of ahdpack
// alone in a folder says it cannot load the module beside it; with the module copied beside it, it
// reads a PNG through it.
TEST(BadInputRound3, OiioModuleFoundBesideTheExecutableOnly) {
  const fs::path d = ahd_test::temp_dir("round3_oiio");
  const fs::path built = AHD_CLI_PATH;
  const fs::path module = built.parent_path() / "libahd_oiio.so";
  if (!fs::exists(module)) GTEST_SKIP() << "no " << module << " beside the built ahdpack";
  ahd::ImageF img(8, 8, 3);
  ahd::write_image((d / "ldr.png").string(), img);
  fs::create_directories(d / "bin");
  fs::copy_file(built, d / "bin" / "ahdpack");
  const std::string cmd = "'" + (d / "bin" / "ahdpack").string() + "' convert '" + (d / "ldr.png").string() + "' -o '" +
                          (d / "out" / "x.ktx2").string() + "' 2>&1; echo rc=$?";
  std::string out = ahd_test::run_shell(cmd);
  EXPECT_TRUE(contains(out, "module cannot be loaded")) << out;
  EXPECT_TRUE(contains(out, (d / "bin" / "libahd_oiio.so").string())) << out;
  EXPECT_FALSE(contains(out, module.string())) << out;
  EXPECT_TRUE(contains(out, "rc=1")) << out;
  fs::copy_file(module, d / "bin" / "libahd_oiio.so");
  out = ahd_test::run_shell(cmd);
  EXPECT_TRUE(contains(out, "half or float")) << out;  // read through the module: an 8-bit PNG is refused
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

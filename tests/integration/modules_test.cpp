// The modules behind dlopen (src/files/modules.h): a conversion that does not need one runs
// without it, one that does names it in one error line, and the module gives the same bytes as
// always once it is beside the executable.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.h"
#include "test_data.h"

namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

std::string bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

// OpenColorIO: an input in the working space converts with no libahd_ocio.so anywhere near a copied
// ahdpack; --input-space acescg then fails with one line naming the module; with the module beside
// it, the copy writes the same planes as the build tree's ahdpack.
TEST(Modules, OcioLoadedOnlyForAnotherColourSpace) {
  const fs::path d = ahd_test::temp_dir("modules_ocio");
  const fs::path built = AHD_CLI_PATH;
  const fs::path module = built.parent_path() / "libahd_ocio.so";
  if (!fs::exists(module)) GTEST_SKIP() << "no " << module << " beside the built ahdpack (AHD_OCIO=OFF)";
  fs::create_directories(d / "bin");
  fs::copy_file(built, d / "bin" / "ahdpack");
  const std::string copy = "'" + (d / "bin" / "ahdpack").string() + "'";
  const std::string in = (d / "in.exr").string();
  // (writing the sample needs OpenImageIO's module: the build tree's ahdpack writes it)
  ASSERT_TRUE(contains(ahd_test::run_shell("'" + built.string() + "' sample --size 32 -o '" + in + "' 2>&1; echo rc=$?"), "rc=0"));
  auto convert = [&](const std::string& exe, const std::string& out, const std::string& extra) {
    return ahd_test::run_shell(exe + " convert '" + in + "' -o '" + (d / out / "x.ktx2").string() +
                               "' --profile uncompressed -q " + extra + " 2>&1; echo rc=$?");
  };
  EXPECT_TRUE(contains(convert(copy, "plain", ""), "rc=0"));
  std::string out = convert(copy, "aces_missing", "--input-space acescg");
  EXPECT_TRUE(contains(out, "needs OpenColorIO, whose module cannot be loaded")) << out;
  EXPECT_TRUE(contains(out, (d / "bin" / "libahd_ocio.so").string())) << out;
  EXPECT_TRUE(contains(out, "rc=1")) << out;
  EXPECT_FALSE(fs::exists(d / "aces_missing"));
  fs::copy_file(module, d / "bin" / "libahd_ocio.so");
  EXPECT_TRUE(contains(convert(copy, "aces_copy", "--input-space acescg"), "rc=0"));
  EXPECT_TRUE(contains(convert("'" + built.string() + "'", "aces_built", "--input-space acescg"), "rc=0"));
  int planes = 0;
  for (const auto& e : fs::directory_iterator(d / "aces_built")) {
    if (e.path().extension() != ".ktx2") continue;
    ++planes;
    EXPECT_EQ(bytes_of(e.path()), bytes_of(d / "aces_copy" / e.path().filename())) << e.path();
  }
  EXPECT_EQ(planes, 3);
  // ACEScg moves the colours: the planes differ from the working-space conversion's.
  EXPECT_NE(bytes_of(d / "aces_built" / "x.json"), bytes_of(d / "plain" / "x.json"));
  fs::remove_all(d);
}

// Assimp: an EXR-only conversion runs with no libahd_assimp.so near a copied ahdpack (which links
// no libassimp), a Godot project whose meshes are glTF fails with one line naming the module and
// writes nothing; with the module beside it, the copy writes the build tree's bytes.
TEST(Modules, AssimpLoadedOnlyWhenAMeshIsRead) {
  const fs::path d = ahd_test::temp_dir("modules_assimp");
  const fs::path built = AHD_CLI_PATH;
  const fs::path module = built.parent_path() / "libahd_assimp.so";
  if (!fs::exists(module)) GTEST_SKIP() << "no " << module << " beside the built ahdpack (AHD_ASSIMP_MODULE=OFF)";
  const fs::path project = ahd_test::test_data("godot/corpus/gltf");
  if (!fs::exists(project / "world.exr")) GTEST_SKIP() << "no " << project;
  fs::create_directories(d / "bin");
  fs::copy_file(built, d / "bin" / "ahdpack");
  const std::string copy = "'" + (d / "bin" / "ahdpack").string() + "'";
  const std::string ldd = ahd_test::run_shell("command -v ldd >/dev/null && ldd " + copy + " 2>&1");
  if (!ldd.empty()) EXPECT_FALSE(contains(ldd, "libassimp")) << ldd;
  const std::string plain = (d / "plain.exr").string();
  ASSERT_TRUE(contains(
      ahd_test::run_shell("'" + built.string() + "' sample --size 32 -o '" + plain + "' 2>&1; echo rc=$?"), "rc=0"));
  auto convert = [&](const std::string& exe, const std::string& in, const std::string& out) {
    return ahd_test::run_shell(exe + " convert '" + in + "' -o '" + (d / out / "x.ktx2").string() +
                               "' --profile uncompressed -q 2>&1; echo rc=$?");
  };
  EXPECT_TRUE(contains(convert(copy, plain, "plain"), "rc=0"));
  const std::string world = (project / "world.exr").string();
  std::string out = convert(copy, world, "missing");
  EXPECT_TRUE(contains(out, ".glb: needs Assimp, whose module cannot be loaded")) << out;
  EXPECT_TRUE(contains(out, (d / "bin" / "libahd_assimp.so").string())) << out;
  EXPECT_TRUE(contains(out, "rc=1")) << out;
  EXPECT_FALSE(fs::exists(d / "missing"));
  fs::copy_file(module, d / "bin" / "libahd_assimp.so");
  EXPECT_TRUE(contains(convert(copy, world, "copy"), "rc=0"));
  EXPECT_TRUE(contains(convert("'" + built.string() + "'", world, "built"), "rc=0"));
  int planes = 0;
  for (const auto& e : fs::directory_iterator(d / "built")) {
    if (e.path().extension() != ".ktx2") continue;
    ++planes;
    EXPECT_EQ(bytes_of(e.path()), bytes_of(d / "copy" / e.path().filename())) << e.path();
  }
  EXPECT_EQ(planes, 3);
  fs::remove_all(d);
}

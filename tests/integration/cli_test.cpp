// The command line as a user meets it: the built-in sample end to end, files re-read bit for bit,
// and every bad input giving one clear line, a non-zero exit and no output files.
#include <gtest/gtest.h>

#include <ahd/ahd.h>
#include <ahd/convert.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli_runner.h"
#include "containers/container.h"
#include "files/container_file.h"
#include "core/image.h"
#include "files/profile_file.h"
#include "image/image_io.h"
#include "image/sh_exr.h"
#include "pipeline/convert.h"
#include "pipeline/plane_codec.h"
#include "sample/analytic_baker.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

int count_lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

size_t files_in(const fs::path& d) {
  size_t n = 0;
  if (!fs::exists(d)) return 0;
  for (auto it = fs::recursive_directory_iterator(d); it != fs::recursive_directory_iterator(); ++it) n += it->is_regular_file();
  return n;
}

// Expects failure with exactly one line on the terminal, naming `needle`, and nothing written in `out_dir`.
void expect_clean_failure(const std::vector<std::string>& args, const std::string& needle, const fs::path& out_dir) {
  const auto r = run_cli(args);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.output;
  EXPECT_EQ(files_in(out_dir), 0u) << "partial output left in " << out_dir;
}

}  // namespace

TEST(Cli, ConvertBuiltInSampleWritesPlanesManifestAndReport) {
  const fs::path d = ahd_test::temp_dir("cli_sample");
  for (const char* ext : {"ktx2", "dds"}) {
    const fs::path out = d / (std::string("s.") + ext);
    const auto r = run_cli({"convert", "-o", out.string(), "--sample-size", "48"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("fit: constrained AHD"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("total"), std::string::npos);
    for (const char* plane : {"iz", "dir", "ratio"}) {
      const std::string f = ahd_test::plane_file((d / "s.json").string(), plane);
      EXPECT_TRUE(fs::exists(f)) << plane;
      EXPECT_EQ(fs::path(f).extension().string(), std::string(".") + ext);
    }
    EXPECT_TRUE(fs::exists(d / "s.json"));
    EXPECT_TRUE(fs::exists(d / "s.report.json"));

    // Re-read by our own reader: the same planes, bit for bit, as the library produces in memory.
    ahd::BakerOptions bo;
    bo.width = bo.height = 48;
    const ahd::PipelineOptions defaults;  // the CLI's defaults are the public ones (<ahd/convert.h>)
    const ahd::PipelineResult mem =
        ahd::run_conversion(ahd::bake_analytic_scene(bo), ahd::load_profile("uncompressed"), defaults);
    for (const auto& p : mem.planes) {
      const ahd::Texture t = ahd::read_container_file(ahd_test::plane_file((d / "s.json").string(), p.name));
      ASSERT_EQ(t.format, p.texture.format);
      ASSERT_EQ(t.levels.size(), p.texture.levels.size());
      for (size_t l = 0; l < t.levels.size(); ++l) EXPECT_EQ(t.levels[l].data, p.texture.levels[l].data) << p.name;
    }

    // decode reconstructs irradiance; inspect describes the files.
    const auto dec = run_cli({"decode", (d / "s.json").string(), "-o", (d / "e.exr").string()});
    ASSERT_EQ(dec.exit_code, 0) << dec.output;
    const ahd::ImageF e = ahd::read_image((d / "e.exr").string());
    EXPECT_EQ(e.width, 48);
    EXPECT_EQ(e.channels, 3);
    const auto ins = run_cli({"inspect", (d / "s.json").string()});
    ASSERT_EQ(ins.exit_code, 0) << ins.output;
    EXPECT_NE(ins.output.find("rgba16f"), std::string::npos) << ins.output;
    fs::remove_all(d);
    fs::create_directories(d);
  }
  fs::remove_all(d);
}

TEST(Cli, FullMipChainsByDefaultAndDecodeLevel) {
  const fs::path d = ahd_test::temp_dir("cli_mips");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "m.dds").string(), "--sample-size", "40", "-q"}).exit_code, 0);
  const ahd::Texture t = ahd::read_container_file(ahd_test::plane_file((d / "m.json").string(), "iz"));
  ASSERT_EQ(t.levels.size(), 6u);  // 40, 20, 10, 5, 2, 1
  EXPECT_EQ(t.levels[3].width, 5u);
  const auto r = run_cli({"decode", (d / "m.json").string(), "--level", "3", "-o", (d / "e3.exr").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const ahd::ImageF e = ahd::read_image((d / "e3.exr").string());
  EXPECT_EQ(e.width, 5);
  EXPECT_EQ(e.height, 5);
  // Along the normal the decode is I_z itself: the decoded level must equal the iz plane's level 3.
  const ahd::ImageF iz = ahd::decode_plane(t.format, t.levels[3]);
  for (size_t i = 0; i < e.texels(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.data[i * 3 + c], iz.data[i * iz.channels + c], 1e-6f * (1 + iz.data[i * iz.channels + c]));
  const auto bad = run_cli({"decode", (d / "m.json").string(), "--level", "6", "-o", (d / "e6.exr").string()});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--level 6 does not exist"), std::string::npos) << bad.output;
  EXPECT_EQ(run_cli({"convert", "-o", (d / "one.ktx2").string(), "--sample-size", "40", "--levels", "1", "-q"}).exit_code, 0);
  EXPECT_EQ(ahd::read_container_file(ahd_test::plane_file((d / "one.json").string(), "iz")).levels.size(), 1u);
  // The optional coverage plane: R8, 255 on charts, 0 in gutters, with its own mip chain.
  ASSERT_EQ(run_cli({"convert", "-o", (d / "c.ktx2").string(), "--sample-size", "40", "--coverage-plane", "-q"}).exit_code, 0);
  const ahd::Texture cov = ahd::read_container_file(ahd_test::plane_file((d / "c.json").string(), "coverage"));
  EXPECT_EQ(cov.format, ahd::PixelFormat::R8_UNORM);
  EXPECT_EQ(cov.levels.size(), 6u);
  EXPECT_EQ(cov.levels[0].data[0], 0);      // corner: gutter
  EXPECT_EQ(cov.levels[0].data[5 * 40 + 5], 255);  // inside the floor chart
  fs::remove_all(d);
}

TEST(Cli, ConvertReadsCanonicalExr) {
  const fs::path d = ahd_test::temp_dir("cli_canon");
  ahd::BakerOptions bo;
  bo.width = bo.height = 20;
  bo.coeffs = 4;
  ahd::write_canonical_sh((d / "in.exr").string(), ahd::bake_analytic_scene(bo));
  const auto r = run_cli({"convert", (d / "in.exr").string(), "-o", (d / "out" / "x.ktx2").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(ahd_test::plane_file((d / "out" / "x.json").string(), "iz")));
  fs::remove_all(d);
}

TEST(Cli, MissingInputFile) {
  const fs::path d = ahd_test::temp_dir("cli_missing");
  expect_clean_failure({"convert", (d / "nope.exr").string(), "-o", (d / "out" / "x.ktx2").string()}, "nope.exr: file not found",
                       d / "out");
  fs::remove_all(d);
}

// UTF-8 names (docs/platforms.md "Windows": files/utf8_path.h): a non-ASCII folder and file convert to
// the same planes as an ASCII name, leave no temporary behind, and a missing one is named as given.
TEST(Cli, NonAsciiNamesConvertLikeAsciiOnes) {
  const fs::path d = ahd_test::temp_dir("cli_utf8");
  const std::string dir = (d / "plain \xC3\xA9 \xE5\x85\x89").string();  // "plain é 光"
  fs::create_directories(dir);
  ahd::BakerOptions bo;
  bo.width = bo.height = 20;
  bo.coeffs = 4;
  const ahd::ShImage sh = ahd::bake_analytic_scene(bo);
  ahd::write_canonical_sh(dir + "/map \xC3\xA9.exr", sh);
  ahd::write_canonical_sh((d / "map.exr").string(), sh);
  const auto r = run_cli({"convert", dir + "/map \xC3\xA9.exr", "-o", dir + "/out \xE5\x85\x89/map \xC3\xA9.ktx2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(run_cli({"convert", (d / "map.exr").string(), "-o", (d / "out" / "map.ktx2").string()}).exit_code, 0);
  const auto read_bytes = [](const std::string& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string iz = ahd_test::plane_file(dir + "/out \xE5\x85\x89/map \xC3\xA9.json", "iz");
  ASSERT_TRUE(fs::exists(iz)) << iz;
  EXPECT_EQ(read_bytes(iz), read_bytes(ahd_test::plane_file((d / "out" / "map.json").string(), "iz")));
  for (const auto& e : fs::directory_iterator(dir + "/out \xE5\x85\x89"))
    EXPECT_EQ(e.path().filename().string().find(".ahdtmp-"), std::string::npos) << e.path();
  expect_clean_failure({"convert", dir + "/absent \xE5\x85\x89.exr", "-o", (d / "none" / "x.ktx2").string()},
                       dir + "/absent \xE5\x85\x89.exr: file not found", d / "none");
  fs::remove_all(d);
}

TEST(Cli, WrongChannelSet) {
  const fs::path d = ahd_test::temp_dir("cli_channels");
  ahd::ImageF img(8, 8, 2);  // (a lone RGB EXR is a plain lightmap: BakerPlain.*)
  ahd::write_image((d / "rgb.exr").string(), img);
  expect_clean_failure({"convert", (d / "rgb.exr").string(), "-o", (d / "out" / "x.ktx2").string()}, "no SH channels", d / "out");
  // An L1 set missing one channel.
  ahd::ImageF l1(8, 8, 11);
  std::vector<std::string> names;
  for (int k = 0; k < 4; ++k)
    for (const char* c : {"R", "G", "B"}) names.push_back("sh" + std::to_string(k) + "." + c);
  names.erase(names.begin() + 4);  // drop sh1.G
  ahd::write_image((d / "l1.exr").string(), l1, false, names);
  expect_clean_failure({"convert", (d / "l1.exr").string(), "-o", (d / "out" / "x.ktx2").string()}, "missing channel sh1.G",
                       d / "out");
  fs::remove_all(d);
}

TEST(Cli, NonFloatImageWhereFloatsAreNeeded) {
  const fs::path d = ahd_test::temp_dir("cli_8bit");
  ahd::ImageF img(8, 8, 3);
  ahd::write_image((d / "ldr.png").string(), img);
  expect_clean_failure({"convert", (d / "ldr.png").string(), "-o", (d / "out" / "x.ktx2").string()}, "half or float", d / "out");
  fs::remove_all(d);
}

TEST(Cli, MismatchedSizesNormalMap) {
  const fs::path d = ahd_test::temp_dir("cli_sizes");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "s.ktx2").string(), "--sample-size", "16", "-q"}).exit_code, 0);
  ahd::ImageF n(8, 8, 3);
  ahd::write_image((d / "n.exr").string(), n);
  expect_clean_failure({"decode", (d / "s.json").string(), "--normals", (d / "n.exr").string(), "-o", (d / "out" / "e.exr").string()},
                       "normal map is 8x8", d / "out");
  fs::remove_all(d);
}

TEST(Cli, UnknownProfileAndContainer) {
  const fs::path d = ahd_test::temp_dir("cli_profile");
  expect_clean_failure({"convert", "-o", (d / "out" / "x.ktx2").string(), "--profile", "nope"}, "unknown profile 'nope'", d / "out");
  expect_clean_failure({"convert", "-o", (d / "out" / "x.png").string()}, "x.png", d / "out");
  fs::remove_all(d);
}

TEST(Cli, CorruptContainerIsRefused) {
  const fs::path d = ahd_test::temp_dir("cli_corrupt");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "s.ktx2").string(), "--sample-size", "16", "-q"}).exit_code, 0);
  // Truncate a plane: inspect and decode must refuse it with one line.
  const std::string iz = ahd_test::plane_file((d / "s.json").string(), "iz");
  fs::resize_file(iz, 100);
  for (auto args : {std::vector<std::string>{"inspect", iz},
                    std::vector<std::string>{"decode", (d / "s.json").string(), "-o", (d / "out" / "e.exr").string()}}) {
    const auto r = run_cli(args);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find(iz + ": "), std::string::npos) << r.output;
  }
  EXPECT_EQ(files_in(d / "out"), 0u);
  fs::remove_all(d);
}

TEST(Cli, CompressDecompressBc6h) {
  const fs::path d = ahd_test::temp_dir("cli_bc6h");
  ahd::ImageF img(13, 6, 3);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 13; ++x)
      for (int ch = 0; ch < 3; ++ch) img.at(x, y)[ch] = 0.5f + 0.3f * x + 0.1f * y + 0.2f * ch;  // smooth
  ahd::write_image((d / "in.exr").string(), img);
  const auto c = run_cli({"compress", (d / "in.exr").string(), "-o", (d / "o.ktx2").string(), "--quality", "fast"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("log-RMSE"), std::string::npos);
  const auto x = run_cli({"decompress", (d / "o.ktx2").string(), "-o", (d / "back.exr").string()});
  ASSERT_EQ(x.exit_code, 0) << x.output;
  const ahd::ImageF back = ahd::read_image((d / "back.exr").string());
  ASSERT_EQ(back.width, 13);
  for (size_t i = 0; i < img.texels(); ++i)
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(back.data[i * back.channels + ch], img.data[i * 3 + ch], 0.05f * (1 + img.data[i * 3 + ch]));
  // Bad input: one line each, nothing written.
  expect_clean_failure({"compress", (d / "in.exr").string(), "-o", (d / "out" / "o.ktx2").string(), "--quality", "ultra"},
                       "--quality", d / "out");
  ASSERT_EQ(run_cli({"convert", "-o", (d / "s.ktx2").string(), "--sample-size", "8", "-q"}).exit_code, 0);
  expect_clean_failure({"decompress", ahd_test::plane_file((d / "s.json").string(), "dir"), "-o", (d / "out" / "x.exr").string()}, "not BC6H",
                       d / "out");
  fs::remove_all(d);
}

TEST(Cli, EveryProfileAndContainerRoundTrips) {
  const fs::path d = ahd_test::temp_dir("cli_profiles");
  for (const std::string& profile : ahd::list_profiles())
    for (const char* ext : {"ktx2", "dds"}) {
      const fs::path out = d / (profile + "." + ext);
      const ahd::Profile p = ahd::load_profile(profile);
      // A profile whose formats the container cannot hold (the registry's row says which) is refused.
      bool holds = true;
      const std::vector<ahd::PixelFormat> formats =
          p.packed_dir_ratio ? std::vector{p.iz, p.dirratio} : std::vector{p.iz, p.dir, p.ratio};
      for (ahd::PixelFormat f : formats)
        holds &=
            ahd::container_holds(ext == std::string("dds") ? ahd::ContainerKind::DDS : ahd::ContainerKind::KTX2, f);
      if (!holds) {
        expect_clean_failure(
            {"convert", "-o", (d / "refused" / out.filename()).string(), "--sample-size", "24", "--profile", profile},
            "cannot hold", d / "refused");
        continue;
      }
      const auto r = run_cli({"convert", "-o", out.string(), "--sample-size", "24", "--profile", profile, "-q"});
      ASSERT_EQ(r.exit_code, 0) << profile << " " << ext << ": " << r.output;
      // The files hold exactly what the library produces for the same input.
      ahd::BakerOptions bo;
      bo.width = bo.height = 24;
      ahd::PipelineOptions opt;
      if (p.ratio_rgb) opt.fit.ratio_form = ahd::RatioForm::Rgb;
      const ahd::PipelineResult mem = ahd::run_conversion(ahd::bake_analytic_scene(bo), p, opt);
      for (const auto& plane : mem.planes) {
        const ahd::Texture t = ahd::read_container_file(ahd_test::plane_file((d / (profile + ".json")).string(), plane.name));
        ASSERT_EQ(t.format, plane.texture.format) << profile << " " << plane.name;
        ASSERT_EQ(t.levels.size(), plane.texture.levels.size());
        for (size_t l = 0; l < t.levels.size(); ++l)
          EXPECT_EQ(t.levels[l].data, plane.texture.levels[l].data) << profile << " " << ext << " " << plane.name << " level " << l;
      }
    }
  fs::remove_all(d);
}

TEST(Cli, BatchConvertsEveryInputPastAFailureAndNamesIt) {
  const fs::path d = ahd_test::temp_dir("cli_batch");
  ahd::BakerOptions bo;
  bo.width = bo.height = 16;
  bo.coeffs = 4;
  ahd::write_canonical_sh((d / "a.exr").string(), ahd::bake_analytic_scene(bo));
  bo.seed = 3;
  ahd::write_canonical_sh((d / "c.exr").string(), ahd::bake_analytic_scene(bo));
  {
    std::ofstream bad(d / "b.exr", std::ios::binary);
    bad << "not an EXR at all";
  }
  const auto r = run_cli({"convert", (d / "a.exr").string(), (d / "b.exr").string(), (d / "c.exr").string(), "-o",
                          (d / "out/").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  // The corrupt file: its one error line, the final line naming it, and nothing written for it.
  EXPECT_NE(r.output.find("ahdpack: error: " + (d / "b.exr").string() + ": "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 of 3 conversions failed: " + (d / "b.exr").string()), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out" / "b.json"));
  for (const auto& e : fs::directory_iterator(d / "out")) EXPECT_NE(e.path().filename().string().rfind("b.", 0), 0u) << e.path();
  // The others converted, each with its own manifest and readable planes, and the summary lists all three.
  for (const char* name : {"a", "c"}) {
    const std::string iz = ahd_test::plane_file((d / "out" / (std::string(name) + ".json")).string(), "iz");
    ASSERT_FALSE(iz.empty()) << name;
    EXPECT_EQ(ahd::read_container_file(iz).levels[0].width, 16u);
  }
  EXPECT_NE(r.output.find("FAILED"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("16x16"), std::string::npos) << r.output;
  // A folder as input converts its .exr files (the corrupt one fails again).
  const auto f = run_cli({"convert", d.string(), "-o", (d / "out2").string() + "/", "--container", "dds", "-q"});
  EXPECT_EQ(f.exit_code, 1) << f.output;
  EXPECT_TRUE(fs::exists(d / "out2" / "a.json"));
  EXPECT_FALSE(ahd_test::plane_file((d / "out2" / "c.json").string(), "iz").empty());
  fs::remove_all(d);
}

// Progress: one line per stage, redrawn in place ('\r') on a terminal — here a pseudo-terminal made
// by util-linux's `script` — and nothing of it in a pipe or with -q.
TEST(Cli, ProgressOnATerminalOnlyNotInPipes) {
  const fs::path d = ahd_test::temp_dir("cli_progress");
  const auto shell = ahd_test::run_shell;
  const std::string convert = std::string("'") + AHD_CLI_PATH + "' convert --sample-size 64 -o '" + (d / "t.ktx2").string() + "'";
  const std::string tty = shell("script -qec \"" + convert + "\" /dev/null 2>&1");
  EXPECT_NE(tty.find("fit"), std::string::npos) << tty;
  EXPECT_NE(tty.find("encode"), std::string::npos) << tty;
  EXPECT_NE(tty.find("\r\033[K"), std::string::npos) << tty;  // redrawn in place
  EXPECT_NE(tty.find("100 %"), std::string::npos) << tty;
  const std::string piped = shell(convert + " 2>&1 | cat");
  EXPECT_EQ(piped.find("\r\033[K"), std::string::npos) << piped;
  EXPECT_EQ(piped.find(" %  "), std::string::npos) << piped;
  EXPECT_NE(piped.find("profile uncompressed"), std::string::npos) << piped;  // the summary still prints
  const std::string quiet = shell("script -qec \"" + convert + " -q\" /dev/null 2>&1");
  EXPECT_EQ(quiet.find("\r\033[K"), std::string::npos) << quiet;
  fs::remove_all(d);
}

// `ahdpack --version`: one line naming the tool and the library's version, exit 0, nothing else run.
TEST(Cli, VersionFlagPrintsTheLibraryVersion) {
  const ahd_test::CliResult r = ahd_test::run_cli({"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, std::string("ahdpack ") + ahd_version() + "\n");
}

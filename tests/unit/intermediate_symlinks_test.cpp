// Issue 44: the intermediate reader (image/ahd_intermediate.cpp, what `transcode` reads) on symlinks.
// A loop — two links naming each other, or a link to its own folder followed past the kernel's
// limit — is one ahd::Error "<path>: symbolic links loop (…)" (std::filesystem threw, which the
// command printed as an internal error, exit 2); a link leading out of its folder to an
// intermediate is followed (the user named it) and reads the same levels; a dangling link is "file
// not found"; a link to a folder or a FIFO is "not a regular file", without blocking. The image
// reader (image/image_io.cpp) says the same of a loop. Unit tests: in process, no CLI.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "core/error.h"
#include "image/ahd_intermediate.h"
#include "image/image_io.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"

namespace fs = std::filesystem;
using namespace ahd;

namespace {

// The ahd::Error read_intermediate(path) throws ("" when it reads, "not ahd::Error: …" for anything else).
std::string intermediate_error(const std::string& path) {
  try {
    read_intermediate(path, nullptr);
    return "";
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("not ahd::Error: ") + e.what();
  }
}

std::vector<FittedLevel> small_levels() {
  BakerOptions bo;
  bo.width = bo.height = 8;
  bo.area_samples = 1;
  PipelineOptions opt;
  opt.threads = 1;
  PipelineResult r;
  return fit_levels(bake_analytic_scene(bo), opt, &r);
}

}  // namespace

TEST(IntermediateSymlinksUnit, LoopIsOneErrorAndALinkOutsideIsFollowed) {
  const fs::path d = ahd_test::temp_dir("intermediate_links");
  fs::create_directories(d / "a");
  fs::create_directories(d / "b");
  const std::vector<FittedLevel> levels = small_levels();
  write_intermediate((d / "a" / "x.ahd.exr").string(), levels, FitOptions{});

  // Two links naming each other.
  fs::create_symlink("loop2.ahd.exr", d / "b" / "loop1.ahd.exr");
  fs::create_symlink("loop1.ahd.exr", d / "b" / "loop2.ahd.exr");
  const std::string loop = (d / "b" / "loop1.ahd.exr").string();
  EXPECT_EQ(intermediate_error(loop).rfind(loop + ": symbolic links loop", 0), 0u) << intermediate_error(loop);
  EXPECT_EQ(intermediate_error(loop).find('\n'), std::string::npos);

  // A link to its own folder, followed 50 times in one path (the kernel stops at 40).
  fs::create_symlink(".", d / "b" / "self");
  std::string deep = (d / "b").string();
  for (int i = 0; i < 50; ++i) deep += "/self";
  deep += "/x.ahd.exr";
  EXPECT_EQ(intermediate_error(deep).rfind(deep + ": symbolic links loop", 0), 0u) << intermediate_error(deep);

  // Out of its folder to a real intermediate: the same levels as the file itself.
  fs::create_symlink("../a/x.ahd.exr", d / "b" / "out.ahd.exr");
  const std::vector<FittedLevel> via = read_intermediate((d / "b" / "out.ahd.exr").string(), nullptr);
  ASSERT_EQ(via.size(), levels.size());
  for (size_t l = 0; l < levels.size(); ++l) EXPECT_EQ(via[l].sh.data, levels[l].sh.data) << l;

  // Dangling; to a folder; to a FIFO (refused unread: nothing blocks).
  fs::create_symlink("gone.ahd.exr", d / "b" / "dangling.ahd.exr");
  const std::string dangling = (d / "b" / "dangling.ahd.exr").string();
  EXPECT_EQ(intermediate_error(dangling), dangling + ": file not found");
  fs::create_symlink("../a", d / "b" / "folder.ahd.exr");
  const std::string folder = (d / "b" / "folder.ahd.exr").string();
  EXPECT_EQ(intermediate_error(folder), folder + ": not a regular file");
  ASSERT_EQ(::mkfifo((d / "a" / "fifo").c_str(), 0600), 0);
  fs::create_symlink("../a/fifo", d / "b" / "fifo.ahd.exr");
  const std::string fifo = (d / "b" / "fifo.ahd.exr").string();
  EXPECT_EQ(intermediate_error(fifo), fifo + ": not a regular file");

  // The image reader on the same loop: the loop, not "file not found".
  try {
    read_image(loop);
    ADD_FAILURE() << "read a loop";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(loop + ": symbolic links loop", 0), 0u) << e.what();
  }
  fs::remove_all(d);
}

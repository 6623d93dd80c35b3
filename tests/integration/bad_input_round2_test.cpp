// Issue 26's bad inputs that need the command or a process of their own: a file replaced while read,
// a bad size variable, the catalogue under a 3 GiB address limit. In-process cases:
// tests/unit/bad_input_round2_test.cpp.
#include <gtest/gtest.h>

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <thread>
#include <tuple>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "expect_error.h"
#include "limited_run.h"
#include "fixture_writers.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "sanitized.h"
#include "containers/ktx2.h"
#include "containers/limits.h"
#include "core/texture.h"
#include "core/error.h"
#include "fit/fit_image.h"
#include "image/ahd_intermediate.h"
#include "bakers/baker_layout.h"
#include "image/colour_space.h"
#include "image/image_io.h"
#include "files/file_io.h"
#include "bakers/layout_detect.h"
#include "bakers/layout_pages.h"
#include "scene/mesh_io.h"
#include "scene/placement_io.h"
#include "files/profile_file.h"
#include "image/sh_exr.h"
#include "scene/lightmap_raster.h"
#include "pipeline/profile.h"
#include "sh/sh_image.h"
#include "bad_input_round2_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::bad_input_round2_fixture;


// 10. An input file replaced while it is read: a header from one file and pixels from the other
// overflowed the heap. Now every read sees one snapshot: an image of either size, or an error.
TEST(BadInputRound2, InputReplacedWhileReadGivesAnErrorOrOneOfTheFiles) {
  const fs::path d = ahd_test::temp_dir("r2_race");
  write_exr(d / "small.exr", 8, 8, sh_names(4), 0.25f);
  write_exr(d / "large.exr", 64, 256, sh_names(4), 0.25f);
  const std::vector<uint8_t> small = slurp(d / "small.exr"), large = slurp(d / "large.exr");
  const fs::path p = d / "in.exr";
  spit(p, small);
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    // Bounded: rewrites in place (truncate, write) and by rename, alternating sizes, until told.
    for (int i = 0; !stop && i < 200000; ++i) {
      const std::vector<uint8_t>& b = (i & 1) ? large : small;
      if (i % 3 == 0) {
        spit(d / "next.exr", b);
        fs::rename(d / "next.exr", p);
      } else {
        spit(p, b);
      }
    }
  });
  int ok = 0, errors = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < until) {
    try {
      const ShImage img = read_canonical_sh(p.string());
      EXPECT_TRUE((img.width == 8 && img.height == 8) || (img.width == 64 && img.height == 256))
          << img.width << "x" << img.height;
      EXPECT_EQ(img.data.size(), img.texels() * 12u);
      ++ok;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": ", 0), 0u) << e.what();
      ++errors;
    }
  }
  stop = true;
  writer.join();
  std::printf("replaced while read: %d reads, %d errors\n", ok, errors);
  EXPECT_GT(ok + errors, 0);
  fs::remove_all(d);
}

// Weak: bad AHDPACK_MAX_SIZE values were ignored silently.
TEST(BadInputRound2, BadMaxSizeEnvironmentIsAnError) {
  for (const char* bad : {"abc", "0", "-5", "99999999999", "12x"}) {
    const std::string out = ahd_test::run_shell(std::string("AHDPACK_MAX_SIZE='") + bad + "' '" + AHD_CLI_PATH +
                                                "' layouts 2>&1; echo \"rc=$?\"");
    EXPECT_NE(out.find("AHDPACK_MAX_SIZE"), std::string::npos) << bad << ": " << out;
    EXPECT_NE(out.find("rc=1"), std::string::npos) << bad << ": " << out;
  }
  const std::string ok = ahd_test::run_shell(std::string("AHDPACK_MAX_SIZE=4096 '") + AHD_CLI_PATH + "' layouts >/dev/null 2>&1; echo \"rc=$?\"");
  EXPECT_NE(ok.find("rc=0"), std::string::npos) << ok;
}

namespace {

using ahd_test::kSanitized;

using ahd_test::LimitedRun;
using ahd_test::run_cli_limited;

}  // namespace

// Done-when of issue 26: under a 3 GiB address-space limit (ulimit -v 3145728) no crafted input of
// this catalogue needs more than 1 GiB or prints "out of memory"; each is one error line naming it.
TEST(BadInputRound2, CatalogueUnderThreeGibAddressSpaceNeedsUnderOneGib) {
  if (kSanitized) GTEST_SKIP() << "sanitizer builds reserve terabytes of shadow memory: RLIMIT_AS cannot apply";
  const fs::path d = ahd_test::temp_dir("r2_ulimit");
  struct Input {
    std::string name;
    std::vector<std::string> args;
    std::string file;  // the file the error must name
  };
  std::vector<Input> inputs;
  // 5: a canonical L2 EXR claiming 11000² (13 GB before).
  write_exr(d / "l2.exr", 8, 8, sh_names(9));
  claim_exr_size(d / "l2.exr", 11000, 11000);
  inputs.push_back({"exr-11000", {"convert", (d / "l2.exr").string(), "-o", (d / "o1.ktx2").string()}, (d / "l2.exr").string()});
  // 5: a PNG claiming 16000² at 16 bits (4.3 GB as floats).
  write_png_claiming(d / "bomb.png", 16000, 16000);
  inputs.push_back({"png-16000", {"compress", (d / "bomb.png").string(), "-o", (d / "o2.ktx2").string()},
                    (d / "bomb.png").string()});
  // 5: an intermediate claiming 9000² (10 GB before).
  write_intermediate_file(d / "big.ahd.exr", 8, 8);
  claim_exr_size(d / "big.ahd.exr", 9000, 9000, size_t((9000 + 63) / 64) * ((9000 + 63) / 64));
  inputs.push_back({"intermediate-9000", {"transcode", (d / "big.ahd.exr").string(), "-o", (d / "o3.ktx2").string()},
                    (d / "big.ahd.exr").string()});
  // 3, 4: an intermediate with a NaN flag, one with garbage luma.
  write_intermediate_file(d / "flags.ahd.exr", 8, 8, [](OIIO::ImageSpec& spec, std::vector<float>& px) {
    px[size_t(channel_of(spec, "ahd.flags"))] = std::numeric_limits<float>::quiet_NaN();
  });
  inputs.push_back({"flags-nan", {"transcode", (d / "flags.ahd.exr").string(), "-o", (d / "o4.ktx2").string()},
                    (d / "flags.ahd.exr").string()});
  write_intermediate_file(d / "luma.ahd.exr", 8, 8, [](OIIO::ImageSpec& spec, std::vector<float>&) { spec.attribute("ahd:luma", "1e300 0 0"); });
  inputs.push_back({"luma", {"transcode", (d / "luma.ahd.exr").string(), "-o", (d / "o5.ktx2").string()}, (d / "luma.ahd.exr").string()});
  // 1, 2: Godot slices over the height; --pages 1073741825.
  fs::create_directories(d / "g1");
  const fs::path g1 = godot_set(d / "g1", 4, 4, 8);
  inputs.push_back({"godot-slices", {"convert", g1.string(), "-o", (d / "o6.ktx2").string()}, g1.string() + ".import"});
  fs::create_directories(d / "g2");
  write_exr(d / "g2" / "lm.exr", 4, 16, {"R", "G", "B"});
  inputs.push_back({"pages", {"convert", (d / "g2" / "lm.exr").string(), "--layout", "godot4-packed", "--pages", "1073741825",
                              "-o", (d / "o7.ktx2").string()}, (d / "g2" / "lm.exr").string()});
  // 14: a profile whose dir plane is r8.
  spit(d / "r8.json", std::string(R"({"name": "r8", "planes": {"iz": "rgba16f", "dir": "r8", "ratio": "r8"}})"));
  write_exr(d / "ok.exr", 8, 8, sh_names(4));
  inputs.push_back({"profile-r8", {"convert", (d / "ok.exr").string(), "--profile", (d / "r8.json").string(), "-o",
                                   (d / "o8.ktx2").string()}, (d / "r8.json").string()});
  // 13: a 20 000-deep glTF given as --mesh.
  std::string nodes = "[{\"mesh\": 0, \"children\": [1]}";
  for (int i = 1; i < 20000; ++i) nodes += i + 1 < 20000 ? ",{\"children\": [" + std::to_string(i + 1) + "]}" : ",{}";
  spit(d / "deep.gltf", gltf_triangle({0, 1, 2}, nodes + "]"));
  inputs.push_back({"gltf-deep", {"convert", (d / "g2" / "lm.exr").string(), "--layout", "godot4-packed", "--mesh",
                                  (d / "deep.gltf").string(), "-o", (d / "o9.ktx2").string()}, (d / "deep.gltf").string()});
  for (const Input& in : inputs) {
    SCOPED_TRACE(in.name);
    const LimitedRun r = run_cli_limited(in.args, d / (in.name + ".log"), rlim_t(3145728) * 1024);
    std::printf("%-18s exit %d, peak RSS %ld KiB: %s", in.name.c_str(), r.exit_code, r.peak_rss_kb, r.output.c_str());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.rfind("ahdpack: error: " + in.file + ": ", 0), 0u) << r.output;
    EXPECT_EQ(r.output.find("out of memory"), std::string::npos) << r.output;
    EXPECT_LT(r.peak_rss_kb, 1024L * 1024) << r.output;
  }
  fs::remove_all(d);
}

// Chromium judges the preview page: it loads without errors and shows something. The preview
// through the command: tests/integration/preview_chromium_test.cpp.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli_runner.h"
#include "image/image_io.h"
#include "image/sh_exr.h"
#include "sh/sh_image.h"
#include "file_bytes.h"
#include "test_data.h"
#include "preview_chromium_fixture.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

using namespace ahd_fixture::preview_chromium_fixture;

TEST(PreviewChromium, PageLoadsWithoutErrorsAndShowsSomething) {
  if (ahd_test::chromium_binary().empty()) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  Page p("preview_chromium");
  ASSERT_TRUE(fs::exists(p.out / "index.html"));
  // The DOM after load: the page's script writes data-status="ok" only when every image loaded
  // and no script error happened.
  std::string dom;
  const int rc = run(p.chromium("--dump-dom"), p.dir / "dom.err", &dom);
  const std::string log = ahd_test::read_text(p.dir / "dom.err");
  ASSERT_EQ(rc, 0) << log;
  EXPECT_NE(dom.find("data-status=\"ok\""), std::string::npos) << dom.substr(0, 2000) << "\n" << log;
  // The exposure script ran: the filter's red table holds the 256 entries of the log codes.
  const size_t fr = dom.find("id=\"fr\"");
  ASSERT_NE(fr, std::string::npos);
  const size_t tv = dom.find("tablevalues=\"", fr) != std::string::npos ? dom.find("tablevalues=\"", fr)
                                                                         : dom.find("tableValues=\"", fr);
  ASSERT_NE(tv, std::string::npos) << dom.substr(fr, 200);
  const std::string table = dom.substr(tv + 13, dom.find('"', tv + 13) - (tv + 13));
  EXPECT_EQ(std::count(table.begin(), table.end(), ' ') + 1, 256) << table.substr(0, 200);
  // Console messages (errors and uncaught exceptions) appear as CONSOLE lines in chromium's log.
  EXPECT_EQ(log.find("CONSOLE"), std::string::npos) << log;
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;

  // The screenshot: not blank (many distinct luminances, real contrast).
  const fs::path shot = p.dir / "shot.png";
  std::string ignored;
  ASSERT_EQ(run(p.chromium("--window-size=1200,1400 --screenshot='" + shot.string() + "'"), p.dir / "shot.err", &ignored),
            0) << ahd_test::read_text(p.dir / "shot.err");
  const ahd::ImageF s = ahd::read_image(shot.string());
  double lo = 1, hi = 0, sum = 0, sum2 = 0;
  std::vector<int> hist(256, 0);
  for (size_t i = 0; i < s.texels(); ++i) {
    const double l = luminance(s, i);
    lo = std::min(lo, l), hi = std::max(hi, l), sum += l, sum2 += l * l;
    hist[std::clamp(int(l * 255), 0, 255)]++;
  }
  const double mean = sum / double(s.texels()), sd = std::sqrt(std::max(0.0, sum2 / double(s.texels()) - mean * mean));
  EXPECT_GT(hi - lo, 0.5);
  EXPECT_GT(sd, 0.05);
  EXPECT_GT(std::count_if(hist.begin(), hist.end(), [](int n) { return n > 0; }), 64);
}

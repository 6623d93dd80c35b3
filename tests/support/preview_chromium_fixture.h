// What the preview page tests share (tests/judges and tests/integration preview_chromium_test.cpp).
#pragma once
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

namespace ahd_fixture::preview_chromium_fixture {

using namespace ::ahd;

namespace fs = std::filesystem;
using ahd_test::run_cli;

// Runs a shell command; stdout into `out`, stderr into `err`. Returns the exit status.
inline int run(const std::string& cmd, const fs::path& err_file, std::string* out) {
  FILE* p = popen((cmd + " 2>'" + err_file.string() + "'").c_str(), "r");
  char buf[4096];
  size_t n;
  while (p && (n = fread(buf, 1, sizeof buf, p)) > 0) out->append(buf, n);
  const int st = p ? pclose(p) : -1;
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

inline double luminance(const ahd::ImageF& img, size_t i) {
  const float* c = &img.data[i * img.channels];
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

struct Page {
  explicit Page(const std::string& tag) : dir(ahd_test::temp_dir(tag)) { make(); }
  fs::path dir;
  fs::path src = dir / "s.exr", manifest = dir / "conv" / "s.json", out = dir / "page";
  void make() {
    EXPECT_EQ(run_cli({"sample", "-o", src.string(), "--size", "128"}).exit_code, 0);
    auto r = run_cli({"convert", src.string(), "-o", (dir / "conv" / "s.ktx2").string(), "--profile", "pc-bc"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    r = run_cli({"preview", manifest.string(), "--source", src.string(), "-o", out.string() + "/"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
  }
  std::string chromium(const std::string& what) const {
    return "'" + ahd_test::chromium_binary() + "' --headless=new --no-sandbox --disable-gpu --hide-scrollbars "
           "--user-data-dir='" + (dir / "profile").string() + "' --enable-logging=stderr --v=0 "
           "--virtual-time-budget=5000 " + what + " 'file://" + (out / "index.html").string() + "'";
  }
};

}  // namespace ahd_fixture::preview_chromium_fixture

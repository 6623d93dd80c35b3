// A four-page atlas through the command: summary and report cover every page. In-process tests:
// tests/unit/pages_report_test.cpp.
#include <gtest/gtest.h>

#include <ahd/sample.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "core/image.h"
#include "files/file_io.h"
#include "files/profile_file.h"
#include "image/image_io.h"
#include "pipeline/pages.h"
#include "pipeline/report_json.h"
#include "pages_report_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::pages_report_fixture;


namespace {

// An OBJ of `n` unit quads facing +z, objects Q0..Q(n-1), UVs covering [0, 1]².
void write_quads(const std::string& path, int n) {
  std::ofstream f(path);
  for (int q = 0; q < n; ++q) {
    f << "o Q" << q << "\n";
    for (int v = 0; v < 4; ++v) f << "v " << 2 * q + (v == 1 || v == 2) << " " << (v >= 2) << " 0\n";
    f << "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n";
    const int b = 4 * q + 1;
    f << "f " << b << "/" << b << "/" << q + 1 << " " << b + 1 << "/" << b + 1 << "/" << q + 1 << " " << b + 2 << "/" << b + 2
      << "/" << q + 1 << "\n";
    f << "f " << b << "/" << b << "/" << q + 1 << " " << b + 2 << "/" << b + 2 << "/" << q + 1 << " " << b + 3 << "/" << b + 3
      << "/" << q + 1 << "\n";
  }
}

}  // namespace

// The command line on a 4-page Godot-style atlas whose instances are placed on every page: the
// summary counts the instances of all pages (it gave the last page's), prints each page's rules,
// and the report's totals are the sum of its pages.
TEST(Cli, FourPageAtlasSummaryAndReportCoverEveryPage) {
  const fs::path d = ahd_test::temp_dir("pages_summary");
  constexpr int S = 16, kPages = 4;
  // Godot ≥ 4.4 packed layers, lit in every texel (then the coverage is not judged), L1 of both signs.
  ImageF img(S, 4 * S * kPages, 3);
  for (int p = 0; p < kPages; ++p)
    for (int y = 0; y < S; ++y)
      for (int x = 0; x < S; ++x)
        for (int c = 0; c < 3; ++c) {
          img.at(x, y + 4 * S * p)[c] = float(1 + p);
          img.at(x, y + 4 * S * p + S)[c] = float(0.5 + 0.04 * std::sin(0.7 * x + p));      // L1y
          img.at(x, y + 4 * S * p + 2 * S)[c] = float(0.56 + 0.01 * std::cos(0.5 * y));   // L1z: from above
          img.at(x, y + 4 * S * p + 3 * S)[c] = float(0.5 + 0.04 * std::cos(0.9 * y + p));  // L1x
        }
  const std::string atlas = (d / "World.exr").string();
  write_image(atlas, img, /*half=*/true, {"R", "G", "B"});
  std::ofstream(atlas + ".import") << "[remap]\n\nimporter=\"2d_array_texture\"\n\n[params]\n\nslices/horizontal=1\n"
                                      "slices/vertical=16\n";
  // Five quads: one on pages 0, 2 and 3, two side by side on page 1.
  write_quads((d / "quads.obj").string(), 5);
  std::ofstream(d / "p.json") << R"({"placements": [
    {"node": "Q0", "page": 0, "scale": [1, 1], "offset": [0, 0]},
    {"node": "Q1", "page": 1, "scale": [0.5, 1], "offset": [0, 0]},
    {"node": "Q2", "page": 1, "scale": [0.5, 1], "offset": [0.5, 0]},
    {"node": "Q3", "page": 2, "scale": [1, 1], "offset": [0, 0]},
    {"node": "Q4", "page": 3, "scale": [1, 1], "offset": [0, 0]}]})";
  const auto r = ahd_test::run_cli({"convert", atlas, "--layout", "godot4-packed", "--mesh", (d / "quads.obj").string(),
                                    "--placement", (d / "p.json").string(), "-o", (d / "out" / "a.ktx2").string(),
                                    "--measure", "estimate"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "5 instance(s) placed by " + (d / "p.json").string() + " (1 + 2 + 1 + 1 on pages 0-3)"))
      << r.output;
  EXPECT_TRUE(contains(r.output, "1024 texels covered on 4 pages")) << r.output;
  EXPECT_TRUE(contains(r.output, "(all 4 pages)")) << r.output;
  for (int p = 0; p < kPages; ++p) EXPECT_TRUE(contains(r.output, "  page " + std::to_string(p) + ": 256 covered")) << r.output;
  EXPECT_FALSE(contains(r.output, "warning")) << r.output;
  const std::vector<uint8_t> b = read_file_bytes((d / "out" / "a.report.json").string());
  const nlohmann::json j = nlohmann::json::parse(b.begin(), b.end());
  ASSERT_EQ(j.at("pages").size(), size_t(kPages));
  size_t covered = 0, measured = 0;
  for (const auto& p : j.at("pages")) {
    covered += p.at("fit_rules").at("covered").get<size_t>();
    measured += p.at("error").at("quantised_closed_loop").at("texels").get<size_t>();
  }
  EXPECT_EQ(covered, 1024u);
  EXPECT_EQ(j.at("fit_rules").at("covered").get<size_t>(), covered);
  EXPECT_EQ(j.at("error").at("quantised_closed_loop").at("texels").get<size_t>(), measured);
  fs::remove_all(d);
}

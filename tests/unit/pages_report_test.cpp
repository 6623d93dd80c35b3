// Every page everywhere (issue 40): a 4-page atlas's report, rules, error figures, direction decision
// and summary cover every page — totals over the pages and each page's own figures — not page 0's
// (the report) or the last page's (the summary's placement count).
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

namespace fs = std::filesystem;
using namespace ahd;

namespace {

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

// Four different pages of one size: analytic scenes of seeds 1-4 with `k` rows of page k
// uncovered (so that every page has its own counts); page 3's L1 zeroed (alone, it drops the
// direction planes: I_z alone is exact).
std::vector<ShImage> four_pages() {
  std::vector<ShImage> pages;
  for (int k = 0; k < 4; ++k) {
    ShImage sh = bake_sample(32, 1, uint32_t(k + 1), 1);
    for (size_t i = 0; i < size_t(32 * 4 * k); ++i) sh.coverage[i] = 0;
    if (k == 3)
      for (size_t i = 0; i < sh.texels(); ++i)
        for (int j = 3; j < sh.coeffs * 3; ++j) sh.texel(i)[j] = 0;
    pages.push_back(std::move(sh));
  }
  return pages;
}

}  // namespace

TEST(Pages, ReportTotalsEveryPageAndSaysWhichPagesDecidedTheDirection) {
  const std::vector<ShImage> pages = four_pages();
  const Profile profile = load_profile("uncompressed");
  PipelineOptions opt;
  opt.measure = Measure::Full;
  opt.threads = 2;
  std::vector<PipelineResult> per_page;
  const PipelineResult r = convert_pages(pages, profile, opt, &per_page);
  const nlohmann::json j = convert_report_json(r, 0);

  // Each page converted alone, as convert would do it: the figures the totals must add up.
  std::vector<PipelineResult> alone;
  for (const ShImage& p : pages) alone.push_back(run_conversion(p, profile, opt));
  ASSERT_TRUE(alone[0].directional);
  ASSERT_FALSE(alone[3].directional);  // the mixed case: page 3 keeps the planes for the atlas only

  size_t covered = 0, tilted = 0, negative = 0, texels = 0, measured = 0;
  double p99 = 0, weighted = 0;
  for (size_t p = 0; p < 3; ++p) {  // pages 0-2 convert exactly as alone
    p99 = std::max(p99, alone[p].final_error.relative.p99);
    weighted += alone[p].final_error.relative.mean * double(alone[p].final_error.texels);
  }
  p99 = std::max(p99, per_page[3].final_error.relative.p99);
  weighted += per_page[3].final_error.relative.mean * double(per_page[3].final_error.texels);
  for (size_t p = 0; p < 4; ++p) {
    covered += alone[p].fit_stats.covered, tilted += alone[p].fit_stats.dir_clamped;
    negative += alone[p].fit_stats.negative_iz, texels += alone[p].fit_stats.texels;
    measured += per_page[p].final_error.texels;
  }
  ASSERT_NE(covered, 4 * alone[0].fit_stats.covered);  // the pages' counts differ: page 0's ×4 would not pass
  const nlohmann::json& rules = j.at("fit_rules");
  EXPECT_EQ(rules.at("covered").get<size_t>(), covered);
  EXPECT_EQ(rules.at("texels").get<size_t>(), texels);
  EXPECT_EQ(rules.at("horizon_tilted").get<size_t>(), tilted);
  EXPECT_EQ(rules.at("negative_iz").get<size_t>(), negative);
  EXPECT_DOUBLE_EQ(rules.at("horizon_tilted_or_negative_iz_fraction").get<double>(), double(tilted + negative) / double(covered));
  const nlohmann::json& fin = j.at("error").at("quantised_closed_loop");
  EXPECT_EQ(fin.at("texels").get<size_t>(), measured);
  EXPECT_DOUBLE_EQ(fin.at("relative").at("p99").get<double>(), p99);  // the largest page's: a bound of the pooled p99
  EXPECT_NEAR(fin.at("relative").at("mean").get<double>(), weighted / double(measured), 1e-12);
  // Dilation of level 0 over every page.
  size_t guard = 0;
  for (const PipelineResult& a : alone) guard += a.dilate_stats.at(0).guard;
  EXPECT_EQ(j.at("levels").at(0).at("dilation").at("guard").get<size_t>(), guard);
  // The input's L1 figures add up too (page 3's are all zeros).
  const L1Figures l1_3 = measure_l1(pages[3]);
  EXPECT_EQ(l1_3.zero[0], l1_3.values[0]);
  EXPECT_EQ(j.at("input_sh").at("l1_values").at(0).get<size_t>(),
            alone[0].l1.values[0] + alone[1].l1.values[0] + alone[2].l1.values[0] + l1_3.values[0]);

  // Each page's own figures, in order.
  const nlohmann::json& pj = j.at("pages");
  ASSERT_EQ(pj.size(), 4u);
  for (size_t p = 0; p < 4; ++p) {
    EXPECT_EQ(pj[p].at("page").get<size_t>(), p);
    EXPECT_EQ(pj[p].at("fit_rules").at("covered").get<size_t>(), alone[p].fit_stats.covered) << p;
    EXPECT_EQ(pj[p].at("direction").at("planes"), "kept") << p;
  }
  EXPECT_DOUBLE_EQ(pj[1].at("error").at("quantised_closed_loop").at("relative").at("p99").get<double>(),
                   alone[1].final_error.relative.p99);
  // The decision says which pages needed the planes and which keep them for the one plane set.
  const std::string why = j.at("direction").at("reason");
  EXPECT_TRUE(contains(why, "on page(s) 0, 1, 2 of 4")) << why;
  EXPECT_TRUE(contains(why, "page(s) 3 would drop them alone")) << why;
  EXPECT_TRUE(contains(pj[3].at("direction").at("reason").get<std::string>(), "dropped: ")) << pj[3];
  EXPECT_TRUE(contains(pj[3].at("direction").at("reason").get<std::string>(), "kept for the atlas")) << pj[3];
  EXPECT_TRUE(j.at("warnings").empty()) << j.at("warnings");

  // One page: no "pages", the figures its own.
  const nlohmann::json one = convert_report_json(alone[0], 0);
  EXPECT_FALSE(one.contains("pages"));
  EXPECT_EQ(one.at("fit_rules").at("covered").get<size_t>(), alone[0].fit_stats.covered);
}

TEST(Pages, EveryPageDroppingTheDirectionSaysSoForAllOfThem) {
  std::vector<ShImage> pages = four_pages();
  for (ShImage& sh : pages)
    for (size_t i = 0; i < sh.texels(); ++i)
      for (int j = 3; j < sh.coeffs * 3; ++j) sh.texel(i)[j] = 0;
  const PipelineResult r = convert_pages(pages, load_profile("uncompressed"), PipelineOptions{});
  EXPECT_FALSE(r.directional);
  EXPECT_TRUE(contains(r.direction_reason, "dropped: ")) << r.direction_reason;
  EXPECT_TRUE(contains(r.direction_reason, "every one of the 4 pages")) << r.direction_reason;
}

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

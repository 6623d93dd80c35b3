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
#include "pages_report_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::pages_report_fixture;

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

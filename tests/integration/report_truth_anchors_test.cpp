// `ahdpack report truth` on the path-traced area scene (tests/data/truth/area): the engine anchors
// (src/lab/truth_baker_formats.h) appear at their shipped bytes, the float forms of the L1-derived
// formats stay near the truncated L1 SH they store, the quantised ones near their float forms, and
// --plot writes the figure (one point per sized row, ahdpack's profiles joined).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_data.h"

namespace {

struct TruthRow {
  std::string bytes;
  double held_out = -1, bumped = -1;
};

// The cells of a Markdown table row "| a | b | … |", trimmed.
std::vector<std::string> table_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream ls(line.substr(2));
  for (std::string cell; std::getline(ls, cell, '|');) {
    while (!cell.empty() && cell.back() == ' ') cell.pop_back();
    while (!cell.empty() && cell.front() == ' ') cell.erase(0, 1);
    cells.push_back(cell);
  }
  return cells;
}

// The table's rows by name: "| name | bytes | held-out | normal-mapped | p99 |".
std::map<std::string, TruthRow> parse_rows(const std::string& out) {
  std::map<std::string, TruthRow> rows;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("At each anchor", 0) == 0) break;  // the budget table after it has other columns
    if (line.rfind("| ", 0) != 0 || line.find("---") != std::string::npos) continue;
    const std::vector<std::string> cells = table_cells(line);
    if (cells.size() < 4 || cells[0] == "representation") continue;
    rows[cells[0]] = {cells[1], std::stod(cells[2]), std::stod(cells[3])};
  }
  return rows;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(ReportTruthAnchors, AnchorsAtShippedBytesNearTheL1TheyStore) {
  const std::string scene = ahd_test::test_data("truth/area").string();
  AHD_REQUIRE_DATA(scene + "/truth.bin");
  const std::string dir = ahd_test::temp_dir("truth-anchors");
  const std::string svg = dir + "/area.svg";
  const ahd_test::CliResult r = ahd_test::run_cli(
      {"report", "truth", scene, "--search", "20", "--profiles", "pc-bc", "uncompressed", "--plot", svg});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = parse_rows(r.output);
  auto row = [&](const std::string& name) {
    const auto it = rows.find(name);
    EXPECT_NE(it, rows.end()) << name << " missing:\n" << r.output;
    return it == rows.end() ? TruthRow{} : it->second;
  };
  const std::string ldr = "Godot LDR directional (PR #100790): L0 BC6H + direction BC1";
  const std::string half = "Godot LDR directional, direction at 1/2 resolution (PR #108405)";
  const std::string unity = "Unity Directional = Enlighten directional irradiance";
  // Shipped bytes per texel (level 0).
  EXPECT_EQ(row("MonoSH (Bakery): L0 BC6H + L1 RGBA8").bytes, "5.000");
  EXPECT_EQ(row("L1 SH as Godot stores it: 4 BC6H layers").bytes, "4.000");
  EXPECT_EQ(row(ldr).bytes, "1.500");
  EXPECT_EQ(row(half + ": L0 BC6H + direction BC1").bytes, "1.125");
  EXPECT_EQ(row(unity + ": BC6H + RGBA8 (for BC7, favours it)").bytes, "2.000");
  EXPECT_EQ(row("plain lightmap (I_z only): BC6H").bytes, "1.000");

  // The float forms that are L1 SH (Godot's per-channel L1 exactly; one shared luminance vector,
  // MonoSH and Godot's LDR texture, nearly; the half-resolution direction a little further) are
  // near the truncated L1 SH's error.
  const double l1 = row("L1 SH (the same SH truncated), float").held_out;
  ASSERT_GT(l1, 0.0);
  EXPECT_NEAR(row("L1 SH as Godot stores it, float").held_out, l1, 0.005 * l1);
  EXPECT_NEAR(row("MonoSH (Bakery), float").held_out, l1, 0.05 * l1);
  EXPECT_NEAR(row(half + ", float").held_out, l1, 0.10 * l1);
  // Quantised: each within 10 % of its float form.
  EXPECT_NEAR(row(ldr).held_out, row("MonoSH (Bakery), float").held_out, 0.10 * l1);
  EXPECT_NEAR(row(half + ": L0 BC6H + direction BC1").held_out, row(half + ", float").held_out, 0.10 * l1);
  const TruthRow uf = row(unity + ", float"), uq = row(unity + ": BC6H + RGBA8 (for BC7, favours it)");
  EXPECT_NEAR(uq.held_out, uf.held_out, 0.10 * uf.held_out);
  EXPECT_NEAR(row("plain lightmap (I_z only): BC6H").held_out, row("plain lightmap (I_z only), float").held_out,
              0.05 * row("plain lightmap (I_z only), float").held_out);
  // Unity's colour is the lightmap's own I_z (no L1 error along the normal): under the bumped
  // normal field, near the normal, it beats every L1 form.
  EXPECT_LT(uf.bumped, row("L1 SH (the same SH truncated), float").bumped);

  // The plot: 6 engine formats + L2 and L1 SH as peers, 4 profile points, one line per fit.
  std::ifstream in(svg);
  ASSERT_TRUE(in.good()) << svg;
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(count(text, "class=\"point peer\""), 8u);
  EXPECT_EQ(count(text, "class=\"point ours\""), 4u);
  EXPECT_EQ(count(text, "<polyline class=\"line\""), 2u);
  EXPECT_NE(text.find("data-x=\"1.125\""), std::string::npos);
  std::filesystem::remove_all(dir);
}

// Issue 43's budgets on held-out scenes of the corpus (docs/accuracy-real-lighting.md "The corpus"):
// for every engine anchor of 1.125 bytes a texel or more, report truth's budget table names an
// ahdpack profile (default fit) of no more bytes with a lower held-out error. The plain lightmap
// (1 byte) has no ahdpack profile of its size, which the table says.
TEST(ReportTruthBudgets, EveryAnchorHasALowerProfileOfNoMoreBytes) {
  for (const char* name : {"lamps", "emissive", "cornell_sun"}) {
    const std::string scene = ahd_test::test_data(std::string("truth/") + name).string();
    AHD_REQUIRE_DATA(scene + "/truth.json");
    const ahd_test::CliResult r = ahd_test::run_cli(
        {"report", "truth", scene, "--search", "8", "--profiles", "pc-bc", "pc-bc-half", "pc-bc-quarter"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const size_t at = r.output.find("At each anchor's bytes");
    ASSERT_NE(at, std::string::npos) << r.output;
    std::istringstream in(r.output.substr(at));
    size_t anchors = 0;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("| ", 0) != 0 || line.rfind("| anchor", 0) == 0) continue;
      const std::vector<std::string> cells = table_cells(line);
      ASSERT_GE(cells.size(), 7u) << line;
      if (std::stod(cells[1]) < 1.1) {
        EXPECT_EQ(cells[6], "no profile") << name << ": " << line;
        continue;
      }
      ++anchors;
      EXPECT_EQ(cells[6], "yes") << name << ": " << line;
      EXPECT_LE(std::stod(cells[4]), std::stod(cells[1])) << name << ": " << line;
    }
    EXPECT_EQ(anchors, 5u) << name << ":\n" << r.output;  // 1.125, 1.5, 2, 4 and 5 bytes
  }
}

// A Godot corpus project converted by the README's one-line recipe (`ahdpack convert
// PROJECT/.../NAME.exr -o OUT`), and what the conversion says: the summed coverage lines (one per
// page) and the report's fit rules. Shared by tests/integration/godot_corpus_test.cpp and
// tests/integration/godot_corpus_wild_test.cpp.
#pragma once
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace ahd_test {

struct Converted {
  CliResult cli;
  int pages = 0;
  size_t covered = 0, lit = 0, outside = 0, fit_covered = 0, tilted = 0, negative_iz = 0;
  double iou_min = 1;
  double rules_pct() const { return fit_covered ? 100.0 * double(tilted + negative_iz) / double(fit_covered) : 0; }
};

// Converts `exr` into `dir` (NAME.ktx2, NAME.report.json) with `extra` options after the recipe's.
inline Converted convert_recipe(const std::filesystem::path& exr, const std::filesystem::path& dir,
                                const std::vector<std::string>& extra = {}) {
  Converted c;
  std::vector<std::string> args = {"convert", exr.string(), "-o", (dir / (exr.stem().string() + ".ktx2")).string()};
  args.insert(args.end(), extra.begin(), extra.end());
  c.cli = run_cli(args);
  if (c.cli.exit_code != 0) return c;
  const std::string& o = c.cli.output;
  const std::regex line(
      R"(coverage: page (\d+): mesh covers (\d+) texels, lightmap lit (\d+): IoU of the lit charts ([0-9.]+) \(lit far outside the mesh (\d+))");
  for (std::sregex_iterator it(o.begin(), o.end(), line), end; it != end; ++it) {
    ++c.pages;
    c.covered += std::stoul((*it)[2]);
    c.lit += std::stoul((*it)[3]);
    c.iou_min = std::min(c.iou_min, std::stod((*it)[4]));
    c.outside += std::stoul((*it)[5]);
  }
  std::ifstream rf(dir / (exr.stem().string() + ".report.json"));
  if (!rf.good()) return c;
  const nlohmann::json fr = nlohmann::json::parse(rf).at("fit_rules");
  c.fit_covered = fr.at("covered"), c.tilted = fr.at("horizon_tilted"), c.negative_iz = fr.at("negative_iz");
  return c;
}

}  // namespace ahd_test

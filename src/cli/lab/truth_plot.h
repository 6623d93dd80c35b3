// The figure of `ahdpack report truth --plot`: per scene, the held-out error of every
// representation that has a size against its bytes per texel, ahdpack's profiles joined as a line.
#pragma once
#include <string>
#include <vector>

namespace ahd::cli {

struct TruthPlotRow {
  std::string name;       // the table's row name; rows named "ahdpack <profile>, <fit> d" are ours
  double bytes = 0;       // level 0 bytes per texel; 0 = no shipped size (left out of the plot)
  double held_out = 0;    // relative L1 error at the held-out normals
};

// The SVG of one scene (svg_plot.h's plot_svg; deterministic).
std::string truth_plot_svg(const std::string& scene, const std::vector<TruthPlotRow>& rows);

// Where scene `scene`'s plot goes for `--plot OUT`: OUT ending in ".svg" is the file itself for one
// scene, and OUT with "-<scene>" before ".svg" for several; any other OUT is a folder (made if
// missing) holding "truth-<scene>.svg".
std::string truth_plot_path(const std::string& out, const std::string& scene, size_t scenes);

}  // namespace ahd::cli

// Hand-written SVG scatter plots (no dependency, no network): the speed–error and size–error
// figures of `ahdpack bench bc6h --plot` and `ahdpack report profiles --plot`.
#pragma once
#include <string>
#include <vector>

namespace ahd::cli {

struct PlotPoint {
  double x = 0, y = 0;
  std::string label;  // written beside the point (may be empty) and as its <title>
};

struct PlotSeries {
  std::string name;    // legend entry
  std::string kind;    // the points' class: "point ours" or "point peer" (tests count them)
  std::string colour;  // CSS colour
  char marker = 'o';   // 'o' circle, 's' square, 'd' diamond
  std::vector<PlotPoint> points;
  bool joined = false;  // also a line through the points in order of x
};

struct Plot {
  std::string title, x_label, y_label, note;  // note: a small line under the title (source, date)
  bool log_x = true, log_y = true;
  std::vector<PlotSeries> series;
};

// The plot as a standalone SVG document (well-formed XML; text escaped). Each point is one element
// <g class="point …" data-series="…" data-x="…" data-y="…">. Points with x or y ≤ 0 on a log axis,
// or not finite, are left out (counted in a comment). Axes span the data with decade ticks on log
// axes. Deterministic: same plot → same bytes.
std::string plot_svg(const Plot& plot);

}  // namespace ahd::cli

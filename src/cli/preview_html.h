// The page of `ahdpack preview`: one HTML document (inline CSS and script, no network) that shows
// the PNGs written beside it.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/manifest.h"

namespace ahd::cli {

// The heat maps' log scale: relative error 1e-4 (black) … 1 (white).
inline constexpr double kHeatLoExp = -4, kHeatHiExp = 0;

struct MapSummary {
  double mean = 0, p99 = 0, max = 0;
  size_t texels = 0;  // covered
};
// mean / p99 / max of the non-NaN values.
MapSummary summarise_map(const std::vector<float>& v);

struct PreviewPage {
  std::string name;  // the conversion's name (manifest stem)
  Manifest manifest;
  nlohmann::json report;  // NAME.report.json, or null
  double white = 1;       // luminance that the log encoding's exposure 0 shows as white
  std::vector<std::pair<int, int>> level_sizes;
  std::vector<std::pair<std::string, std::string>> irradiance;  // file, caption
  std::string source;  // empty: no heat maps
  MapSummary error_normal, error_hemisphere;
  std::string view3d_html;  // escaped HTML from write_preview_3d (preview_3d.h): the link or a note
};

// The HTML document. Files it names: iz_L<l>.png, dir_L<l>.png, ratio_L<l>.png (directional),
// the irradiance files, error_normal.png / error_hemisphere.png (with a source).
std::string preview_html(const PreviewPage& p);

}  // namespace ahd::cli

#include "cli/lab/truth_plot.h"

#include <filesystem>
#include <utility>

#include "cli/lab/svg_plot.h"
#include "core/error.h"
#include "files/utf8_path.h"

namespace ahd::cli {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// A point's label: the row name up to its first ": " (the storage details stay in the table),
// with the longest phrases shortened to fit beside a point.
std::string short_label(const std::string& name) {
  std::string s = name.substr(0, name.find(": "));
  for (const auto& [from, to] : {std::pair<std::string, std::string>{" = Enlighten directional irradiance", " / Enlighten"},
                                 {", direction at 1/2 resolution", ", half-res direction"},
                                 {" (the same SH truncated)", ""}}) {
    const size_t at = s.find(from);
    if (at != std::string::npos) s.replace(at, from.size(), to);
  }
  return s;
}

}  // namespace

std::string truth_plot_svg(const std::string& scene, const std::vector<TruthPlotRow>& rows) {
  Plot plot;
  plot.title = "Against path-traced lighting: " + scene + " (ahdpack report truth)";
  plot.x_label = "bytes per texel (level 0)";
  plot.y_label = "relative L1 error at held-out normals";
  plot.note = "tests/data/truth/" + scene + "; lines: ahdpack's profiles per direction fit; " +
              "docs/accuracy-real-lighting.md \"Every byte budget\"";
  plot.log_y = false;
  PlotSeries refined{"ahdpack profiles, refined d", "point ours", "#1f77b4", 'o', {}};
  PlotSeries linear{"ahdpack profiles, linear d", "point ours", "#7fb3e0", 'o', {}};
  PlotSeries engines{"engine formats at shipped bytes", "point peer", "#d62728", 's', {}};
  PlotSeries sh{"SH, float", "point peer", "#888888", 'd', {}};
  refined.joined = linear.joined = true;
  for (const TruthPlotRow& r : rows) {
    if (r.bytes <= 0) continue;
    if (r.name.rfind("ahdpack ", 0) == 0) {
      const std::string profile = r.name.substr(8, r.name.find(", ") - 8);
      (ends_with(r.name, "linear d") ? linear : refined).points.push_back({r.bytes, r.held_out, profile});
    } else if (r.name.find("float") != std::string::npos) {  // L2 and L1 SH at their float bytes
      sh.points.push_back({r.bytes, r.held_out, short_label(r.name)});
    } else {
      engines.points.push_back({r.bytes, r.held_out, short_label(r.name)});
    }
  }
  plot.series = {refined, linear, engines, sh};
  return plot_svg(plot);
}

std::string truth_plot_path(const std::string& out, const std::string& scene, size_t scenes) {
  if (ends_with(out, ".svg")) return scenes == 1 ? out : out.substr(0, out.size() - 4) + "-" + scene + ".svg";
  std::error_code ec;
  std::filesystem::create_directories(fs_path(out), ec);
  if (ec) throw file_error(out, "cannot make the plot folder: " + ec.message());
  return utf8_string(fs_path(out) / fs_path("truth-" + scene + ".svg"));
}

}  // namespace ahd::cli

#include "cli/lab/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "cli/markup.h"

namespace ahd::cli {
namespace {

std::string num(double v, const char* f = "%.1f") { return format_number(v, f); }

// One axis: data range → pixel range, with its tick values.
struct Axis {
  bool log = true;
  double lo = 0, hi = 1;  // in axis units (log10 when log)
  double p0 = 0, p1 = 1;  // pixels
  double map(double v) const {
    const double t = ((log ? std::log10(v) : v) - lo) / (hi - lo);
    return p0 + t * (p1 - p0);
  }
  std::vector<double> ticks() const {
    std::vector<double> t;
    if (log) {
      for (int e = int(std::floor(lo)); e <= int(std::ceil(hi)); ++e)
        for (double m : {1.0, 2.0, 5.0}) {
          const double v = m * std::pow(10.0, e);
          if ((m == 1.0 || hi - lo < 2.5) && std::log10(v) >= lo - 1e-9 && std::log10(v) <= hi + 1e-9) t.push_back(v);
        }
    } else {
      const double raw = (hi - lo) / 6, mag = std::pow(10.0, std::floor(std::log10(raw)));
      const double step = raw / mag < 2 ? 2 * mag : raw / mag < 5 ? 5 * mag : 10 * mag;
      for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) t.push_back(v);
    }
    return t;
  }
};

bool usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

Axis make_axis(std::vector<double> v, bool log, double p0, double p1) {
  Axis a;
  a.log = log;
  a.p0 = p0;
  a.p1 = p1;
  if (v.empty()) v = {1, 10};
  double lo = *std::min_element(v.begin(), v.end()), hi = *std::max_element(v.begin(), v.end());
  if (log) {
    lo = std::floor(std::log10(lo) * 4) / 4 - 0.1;  // quarter-decade margins
    hi = std::ceil(std::log10(hi) * 4) / 4 + 0.1;
  } else {
    const double pad = hi > lo ? 0.08 * (hi - lo) : 1;
    lo = std::min(0.0, lo - pad);
    hi += pad;
  }
  a.lo = lo;
  a.hi = hi;
  return a;
}

std::string tick_label(double v) {
  char b[32];
  if (v != 0 && (std::fabs(v) < 1e-2 || std::fabs(v) >= 1e4)) std::snprintf(b, sizeof b, "%.0e", v);
  else std::snprintf(b, sizeof b, "%g", v);
  return b;
}

std::string marker(char m, double x, double y, const std::string& colour) {
  const std::string c = "fill=\"" + xml_escape(colour) + "\" stroke=\"#222\" stroke-width=\"0.6\"";
  if (m == 's') return "<rect x=\"" + num(x - 4.5) + "\" y=\"" + num(y - 4.5) + "\" width=\"9\" height=\"9\" " + c + "/>";
  if (m == 'd')
    return "<polygon points=\"" + num(x) + "," + num(y - 6) + " " + num(x + 6) + "," + num(y) + " " + num(x) + "," +
           num(y + 6) + " " + num(x - 6) + "," + num(y) + "\" " + c + "/>";
  return "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"4.5\" " + c + "/>";
}

}  // namespace

std::string plot_svg(const Plot& plot) {
  const double W = 960, H = 620, L = 90, R = 290, T = 70, B = 60;
  std::vector<double> xs, ys;
  size_t dropped = 0;
  for (const PlotSeries& s : plot.series)
    for (const PlotPoint& p : s.points) {
      if (!usable(p.x, plot.log_x) || !usable(p.y, plot.log_y)) continue;
      xs.push_back(p.x);
      ys.push_back(p.y);
    }
  const Axis ax = make_axis(xs, plot.log_x, L, W - R), ay = make_axis(ys, plot.log_y, H - B, T);
  std::string o = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                  num(W, "%.0f") + "\" height=\"" + num(H, "%.0f") + "\" viewBox=\"0 0 " + num(W, "%.0f") + " " +
                  num(H, "%.0f") + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o += "<text x=\"" + num(L) + "\" y=\"28\" font-size=\"17\" font-weight=\"bold\">" + xml_escape(plot.title) + "</text>\n";
  if (!plot.note.empty()) o += "<text x=\"" + num(L) + "\" y=\"48\" fill=\"#555\">" + xml_escape(plot.note) + "</text>\n";
  // Grid and ticks.
  o += "<g class=\"axes\" stroke=\"#ddd\">\n";
  for (double t : ax.ticks()) {
    const double x = ax.map(t);
    o += "<line x1=\"" + num(x) + "\" y1=\"" + num(T) + "\" x2=\"" + num(x) + "\" y2=\"" + num(H - B) + "\"/>";
    o += "<text x=\"" + num(x) + "\" y=\"" + num(H - B + 16) + "\" text-anchor=\"middle\" stroke=\"none\" fill=\"#333\">" +
         tick_label(t) + "</text>\n";
  }
  for (double t : ay.ticks()) {
    const double y = ay.map(t);
    o += "<line x1=\"" + num(L) + "\" y1=\"" + num(y) + "\" x2=\"" + num(W - R) + "\" y2=\"" + num(y) + "\"/>";
    o += "<text x=\"" + num(L - 6) + "\" y=\"" + num(y + 4) + "\" text-anchor=\"end\" stroke=\"none\" fill=\"#333\">" +
         tick_label(t) + "</text>\n";
  }
  o += "</g>\n<rect x=\"" + num(L) + "\" y=\"" + num(T) + "\" width=\"" + num(W - R - L) + "\" height=\"" +
       num(H - B - T) + "\" fill=\"none\" stroke=\"#333\"/>\n";
  o += "<text x=\"" + num((L + W - R) / 2) + "\" y=\"" + num(H - 18) + "\" text-anchor=\"middle\">" + xml_escape(plot.x_label) +
       (plot.log_x ? " (log)" : "") + "</text>\n";
  o += "<text transform=\"translate(22," + num((T + H - B) / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
       xml_escape(plot.y_label) + (plot.log_y ? " (log)" : "") + "</text>\n";
  // Points, each series in its own group; labels beside the points, moved down or up past labels
  // already placed (boxes estimated at 5.5 px per character, 11 px high).
  struct Box {
    double x0, y0, x1, y1;
  };
  std::vector<Box> placed;
  auto label_y = [&](double x, double y, size_t chars) {
    const double w = 5.5 * double(chars);
    for (double dy : {-5.0, 8.0, -16.0, 19.0, -27.0, 30.0, -38.0, 41.0}) {
      const Box b{x, y + dy - 10, x + w, y + dy + 1};
      const bool free = std::none_of(placed.begin(), placed.end(), [&](const Box& o) {
        return b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1;
      });
      if (free) {
        placed.push_back(b);
        return y + dy;
      }
    }
    return y - 5;
  };
  for (const PlotSeries& s : plot.series) {
    o += "<g class=\"series\" data-series=\"" + xml_escape(s.name) + "\">\n";
    if (s.joined) {
      std::vector<std::pair<double, double>> line;
      for (const PlotPoint& p : s.points)
        if (usable(p.x, plot.log_x) && usable(p.y, plot.log_y)) line.emplace_back(ax.map(p.x), ay.map(p.y));
      std::sort(line.begin(), line.end());
      std::string pts;
      for (const auto& [x, y] : line) pts += (pts.empty() ? "" : " ") + num(x) + "," + num(y);
      if (line.size() > 1)
        o += "<polyline class=\"line\" points=\"" + pts + "\" fill=\"none\" stroke=\"" + xml_escape(s.colour) +
             "\" stroke-width=\"1.5\"/>\n";
    }
    for (const PlotPoint& p : s.points) {
      if (!usable(p.x, plot.log_x) || !usable(p.y, plot.log_y)) {
        ++dropped;
        continue;
      }
      const double x = ax.map(p.x), y = ay.map(p.y);
      o += "<g class=\"" + xml_escape(s.kind) + "\" data-series=\"" + xml_escape(s.name) + "\" data-x=\"" + num(p.x, "%.6g") +
           "\" data-y=\"" + num(p.y, "%.6g") + "\"><title>" + xml_escape(s.name + (p.label.empty() ? "" : ", " + p.label)) +
           "</title>" + marker(s.marker, x, y, s.colour);
      if (!p.label.empty())
        o += "<text x=\"" + num(x + 7) + "\" y=\"" + num(label_y(x + 7, y, p.label.size())) +
             "\" font-size=\"10\" fill=\"#333\">" + xml_escape(p.label) + "</text>";
      o += "</g>\n";
    }
    o += "</g>\n";
  }
  // Legend.
  double ly = T + 10;
  o += "<g class=\"legend\">\n";
  for (const PlotSeries& s : plot.series) {
    o += marker(s.marker, W - R + 24, ly, s.colour) + "<text x=\"" + num(W - R + 36) + "\" y=\"" + num(ly + 4) + "\">" +
         xml_escape(s.name) + "</text>\n";
    ly += 20;
  }
  o += "</g>\n";
  if (dropped) o += "<!-- " + std::to_string(dropped) + " point(s) not drawable on a log axis -->\n";
  o += "</svg>\n";
  return o;
}

}  // namespace ahd::cli

#include "cli/preview_html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli/markup.h"
#include "cli/preview_images.h"
#include "core/pixel_format.h"

namespace ahd::cli {
namespace {

// Every text that reaches the page goes through xml_escape (names, report keys and values,
// manifest strings): the report and manifest are files anyone can edit.
std::string fmt(double v, const char* f = "%.3g") { return format_number(v, f); }

// Displayed width of a level: level 0 scaled by a whole factor to about 256–512 px, mips alike.
int display_width(int w0) { return w0 >= 256 ? std::min(w0, 512) : w0 * std::max(1, 256 / w0); }

std::string figure(const std::string& file, const std::string& caption, int width, bool hdr) {
  return "<figure><img src=\"" + xml_escape(file) + "\" alt=\"" + xml_escape(file) + "\" style=\"width:" + std::to_string(width) +
         "px\"" + (hdr ? " class=\"hdr\"" : "") + "><figcaption>" + xml_escape(caption) + "</figcaption></figure>\n";
}

// Any JSON value as HTML: objects as two-column tables, arrays of objects as tables, else text.
std::string json_html(const nlohmann::json& j) {
  if (j.is_object()) {
    std::string o = "<table>";
    for (auto it = j.begin(); it != j.end(); ++it) o += "<tr><th>" + xml_escape(it.key()) + "</th><td>" + json_html(*it) + "</td></tr>";
    return o + "</table>";
  }
  if (j.is_array() && !j.empty() && j[0].is_object()) {
    std::vector<std::string> keys;
    for (const auto& e : j)
      if (e.is_object())
        for (auto it = e.begin(); it != e.end(); ++it)
          if (std::find(keys.begin(), keys.end(), it.key()) == keys.end()) keys.push_back(it.key());
    std::string o = "<table><tr><th>#</th>";
    for (const auto& k : keys) o += "<th>" + xml_escape(k) + "</th>";
    o += "</tr>";
    for (size_t i = 0; i < j.size(); ++i) {
      o += "<tr><td>" + std::to_string(i) + "</td>";
      for (const auto& k : keys) o += "<td>" + (j[i].is_object() && j[i].contains(k) ? json_html(j[i][k]) : "") + "</td>";
      o += "</tr>";
    }
    return o + "</table>";
  }
  if (j.is_number_float()) return fmt(j.get<double>());
  if (j.is_string()) return xml_escape(j.get<std::string>());
  return xml_escape(j.dump());
}

// The report's error block: one row per stage of the measurement, the usual columns.
std::string error_table(const nlohmann::json& e) {
  std::string o =
      "<table><tr><th>measured</th><th>texels</th><th>rel mean</th><th>rel p99</th><th>rel max</th><th>log2 mean</th>"
      "<th>log2 p99</th><th>I_z rel p99</th><th>I_z rel max</th><th>negative</th></tr>";
  auto cell = [](const nlohmann::json& r, const char* k, const char* s) {
    return "<td>" + (r.contains(k) && r[k].contains(s) && r[k][s].is_number() ? fmt(r[k][s].get<double>()) : "–") + "</td>";
  };
  for (auto it = e.begin(); it != e.end(); ++it) {
    const auto& r = *it;
    if (!r.is_object()) continue;
    o += "<tr><th>" + xml_escape(it.key()) + "</th><td>" + (r.contains("texels") ? json_html(r["texels"]) : "") + "</td>" +
         cell(r, "relative", "mean") + cell(r, "relative", "p99") + cell(r, "relative", "max") + cell(r, "log2", "mean") +
         cell(r, "log2", "p99") + cell(r, "iz_relative", "p99") + cell(r, "iz_relative", "max") + "<td>" +
         (r.contains("negative_texels") ? json_html(r["negative_texels"]) : "") + "</td></tr>";
  }
  return o + "</table>";
}

// Seconds per stage with a bar each (share of the total).
std::string seconds_table(const nlohmann::json& s) {
  double total = s.contains("total") && s["total"].is_number() ? s["total"].get<double>() : 0;
  for (auto it = s.begin(); it != s.end() && total <= 0; ++it)
    if (it->is_number()) total += it->get<double>();
  std::string o = "<table><tr><th>stage</th><th>seconds</th><th>share</th></tr>";
  for (auto it = s.begin(); it != s.end(); ++it) {
    if (!it->is_number()) continue;
    const double v = it->get<double>(), f = total > 0 ? std::clamp(v / total, 0.0, 1.0) : 0;
    o += "<tr><th>" + xml_escape(it.key()) + "</th><td>" + fmt(v, "%.4f") + "</td><td><span class=\"bar\" style=\"width:" +
         fmt(200 * f, "%.0f") + "px\"></span> " + fmt(100 * f, "%.1f") + " %</td></tr>";
  }
  return o + "</table>";
}

std::string legend() {
  std::string g;
  const auto& s = heat_stops();
  for (size_t k = 0; k < s.size(); ++k)
    g += (k ? "," : "") + std::string("rgb(") + fmt(255 * s[k][0], "%.0f") + "," + fmt(255 * s[k][1], "%.0f") + "," +
         fmt(255 * s[k][2], "%.0f") + ")";
  std::string o = "<div class=\"legend\"><div class=\"ramp\" style=\"background:linear-gradient(to right," + g +
                  ")\"></div><div class=\"ticks\">";
  for (int e = int(kHeatLoExp); e <= int(kHeatHiExp); ++e) o += "<span>1e" + std::to_string(e) + "</span>";
  return o + "</div><p>relative error, log scale (clamped at both ends); grey-blue: texel not covered</p></div>\n";
}

const char* kStyle = R"(body{font-family:sans-serif;margin:1.5em;background:#f6f6f6;color:#222}
figure{display:inline-block;margin:0 1em 1em 0;vertical-align:top}figcaption{font-size:12px;color:#444}
img{image-rendering:pixelated;background:#000;display:block}table{border-collapse:collapse;margin:.5em 0;font-size:13px}
th,td{border:1px solid #ccc;padding:2px 6px;text-align:left;vertical-align:top}th{background:#eee}
.bar{display:inline-block;height:10px;background:#4a7fb5}.legend{width:420px}.ramp{height:16px;border:1px solid #888}
.ticks{display:flex;justify-content:space-between;font-size:12px}.legend p{font-size:12px;color:#444;margin:2px 0}
#controls{position:sticky;top:0;background:#f6f6f6;padding:.4em 0;border-bottom:1px solid #ccc}
)";

// Exposure: every HDR <img> goes through filter #exposure; its tables map the log codes of
// preview_images.h to display values 2^ev·x clamped to 1, gamma 2.2.
const char* kScript = R"(
(function () {
  var errors = [];
  window.addEventListener('error', function (e) {
    var t = e.target;
    errors.push(t && t.tagName === 'IMG' ? 'image failed to load: ' + t.getAttribute('src') : String(e.message));
  }, true);
  function table(ev) {
    var v = ['0'];
    for (var k = 1; k < 256; k++) {
      var x = Math.pow(2, LOG_LO + k / 255 * (LOG_HI - LOG_LO) + ev);
      v.push(Math.pow(Math.min(1, x), 1 / 2.2).toFixed(4));
    }
    return v.join(' ');
  }
  function setExposure(ev) {
    var t = table(ev);
    ['fr', 'fg', 'fb'].forEach(function (id) { document.getElementById(id).setAttribute('tableValues', t); });
    document.getElementById('evv').textContent = (ev >= 0 ? '+' : '') + ev.toFixed(2);
  }
  var slider = document.getElementById('ev');
  slider.addEventListener('input', function () { setExposure(parseFloat(slider.value)); });
  setExposure(parseFloat(slider.value));
  window.addEventListener('load', function () {
    var imgs = document.images;
    for (var i = 0; i < imgs.length; i++)
      if (!imgs[i].complete || imgs[i].naturalWidth === 0) errors.push('image not shown: ' + imgs[i].getAttribute('src'));
    document.body.setAttribute('data-status', errors.length ? 'error' : 'ok');
    document.getElementById('status').textContent = errors.length ? 'errors: ' + errors.join('; ') : 'all ' + imgs.length + ' images loaded';
  });
})();
)";

}  // namespace

MapSummary summarise_map(const std::vector<float>& v) {
  std::vector<double> x;
  for (float f : v)
    if (!std::isnan(f)) x.push_back(f);
  MapSummary s;
  s.texels = x.size();
  if (x.empty()) return s;
  for (double d : x) s.mean += d;
  s.mean /= double(x.size());
  std::sort(x.begin(), x.end());
  s.max = x.back();
  s.p99 = x[std::min(x.size() - 1, size_t(std::ceil(0.99 * double(x.size()))) - 1)];
  return s;
}

std::string preview_html(const PreviewPage& p) {
  const Manifest& m = p.manifest;
  const int w0 = display_width(int(m.width));
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>ahdpack preview: " + xml_escape(p.name) +
                  "</title>\n<style>" + kStyle + "</style></head>\n<body data-status=\"loading\">\n";
  h += "<svg width=\"0\" height=\"0\" style=\"position:absolute\" aria-hidden=\"true\"><filter id=\"exposure\" "
       "color-interpolation-filters=\"sRGB\"><feComponentTransfer><feFuncR id=\"fr\" type=\"table\" tableValues=\"0 1\"/>"
       "<feFuncG id=\"fg\" type=\"table\" tableValues=\"0 1\"/><feFuncB id=\"fb\" type=\"table\" tableValues=\"0 1\"/>"
       "</feComponentTransfer></filter></svg>\n";
  h += "<h1>" + xml_escape(p.name) + "</h1>\n<p>profile <b>" + xml_escape(m.profile) + "</b>, " + std::to_string(m.width) + "×" +
       std::to_string(m.height) + ", " + std::to_string(m.levels) + " mip level(s)" +
       (m.layers > 1 ? ", " + std::to_string(m.layers) + " pages (page 0 shown)" : "") + ", " + xml_escape(m.container) +
       ", ratio " + (m.ratio_form == RatioForm::Rgb ? "rgb" : "luminance") + ", ε = " + fmt(m.dz_min) + ", direction " +
       (m.directional ? "planes kept" : "planes dropped (I_z only)") + ", frame " + xml_escape(m.direction_frame) + ".</p>\n";
  h += "<div id=\"controls\">Exposure <input type=\"range\" id=\"ev\" min=\"-10\" max=\"6\" step=\"0.25\" value=\"-1\"> "
       "<span id=\"evv\">0</span> EV (0 EV: luminance " + fmt(p.white) + " = white, the p99 of I_z) · status: "
       "<span id=\"status\">loading</span></div>\n";
  h += p.view3d_html;

  h += "<h2>Irradiance, level 0</h2>\n<p>Decoded with the reference decoder (fit/ahd_decode.h) for the surface normal "
       "and for normals tilted 45°; HDR, shown through the exposure control (8-bit log encoding, 16 stops).</p>\n";
  for (const auto& [file, caption] : p.irradiance) h += figure(file, caption, w0, true);

  if (!p.source.empty()) {
    h += "<h2>Error against the source SH</h2>\n<p>Source: " + xml_escape(p.source) + ". Per covered texel of level 0.</p>\n";
    auto row = [](const char* what, const MapSummary& s) {
      return "<tr><th>" + std::string(what) + "</th><td>" + std::to_string(s.texels) + "</td><td>" + fmt(s.mean) +
             "</td><td>" + fmt(s.p99) + "</td><td>" + fmt(s.max) + "</td></tr>";
    };
    h += "<table><tr><th>relative error</th><th>texels</th><th>mean</th><th>p99</th><th>max</th></tr>" +
         row("along the normal (I_z)", p.error_normal) + row("hemisphere (64 normals)", p.error_hemisphere) + "</table>\n";
    h += figure("error_normal.png", "along the normal: |I(z) − E(z)| / E(z) — what quantisation adds", w0, false);
    h += figure("error_hemisphere.png", "hemisphere: RMS over 64 normals / mean E — the AHD model and quantisation",
                w0, false);
    h += legend();
  }

  h += "<h2>Planes and mip levels</h2>\n<p>iz: HDR (exposure control); dir: 0.5 + 0.5·d; ratio: C_a / I_z.</p>\n<table><tr><th>level</th>";
  std::vector<std::string> planes = {"iz"};
  if (m.directional) planes.insert(planes.end(), {"dir", "ratio"});
  for (const auto& pl : planes) h += "<th>" + pl + "</th>";
  h += "</tr>\n";
  for (size_t l = 0; l < p.level_sizes.size(); ++l) {
    const auto [w, ht] = p.level_sizes[l];
    const int dw = std::max(16, int(std::lround(double(w0) * w / m.width)));
    h += "<tr><th>" + std::to_string(l) + "<br>" + std::to_string(w) + "×" + std::to_string(ht) + "</th>";
    for (const auto& pl : planes)
      h += "<td>" + figure(pl + "_L" + std::to_string(l) + ".png", pl, dw, pl == "iz") + "</td>";
    h += "</tr>\n";
  }
  h += "</table>\n<h3>Files</h3>\n<table><tr><th>plane</th><th>file</th><th>format</th><th>size</th><th>levels</th><th>bytes</th></tr>";
  for (const ManifestPlane& mp : m.planes)
    h += "<tr><td>" + xml_escape(mp.name) + "</td><td>" + xml_escape(mp.file) + "</td><td>" + xml_escape(format_info(mp.format).name) +
         "</td><td>" + std::to_string(mp.width) + "×" + std::to_string(mp.height) + "</td><td>" + std::to_string(mp.levels) +
         "</td><td>" + std::to_string(mp.bytes) + "</td></tr>";
  h += "</table>\n";

  h += "<h2>Report</h2>\n";
  if (!p.report.is_object()) {
    h += "<p>No " + xml_escape(p.name) + ".report.json beside the manifest.</p>\n";
  } else {
    if (p.report.contains("seconds")) h += "<h3>Time per stage</h3>\n" + seconds_table(p.report["seconds"]) + "\n";
    if (p.report.contains("error") && p.report["error"].is_object())
      h += "<h3>Error</h3>\n" + error_table(p.report["error"]) + "\n";
    for (auto it = p.report.begin(); it != p.report.end(); ++it)
      if (it.key() != "seconds" && it.key() != "error") h += "<h3>" + xml_escape(it.key()) + "</h3>\n" + json_html(*it) + "\n";
  }
  h += "<script>var LOG_LO = " + fmt(kLogLo, "%g") + ", LOG_HI = " + fmt(kLogHi, "%g") + ";" + kScript +
       "</script>\n</body></html>\n";
  return h;
}

}  // namespace ahd::cli

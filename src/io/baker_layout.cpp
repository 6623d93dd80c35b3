#include "io/baker_layout.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/image_io.h"
#include "core/paths.h"

namespace ahd {
namespace fs = std::filesystem;

LayoutPreset load_layout(const std::string& name_or_path) {
  const std::string path = data_file_path("bakers", name_or_path);
  std::ifstream f(path);
  if (!f) {
    std::string known;
    for (const auto& n : list_layouts()) known += (known.empty() ? "" : ", ") + n;
    throw file_error(path, "unknown layout '" + name_or_path + "' (known: " + known + ")");
  }
  LayoutPreset p;
  try {
    const nlohmann::json j = nlohmann::json::parse(f);
    p.name = j.at("name").get<std::string>();
    p.description = j.value("description", "");
    if (j.value("reader", "") == "canonical") {
      p.canonical = true;
      return p;
    }
    p.coeffs = j.at("coeffs").get<int>();
    if (p.coeffs != 4 && p.coeffs != 9) throw file_error(path, "coeffs must be 4 or 9");
    const std::string space = j.value("space", "tangent");
    if (space != "tangent" && space != "world") throw file_error(path, "space must be tangent or world");
    p.world_space = space == "world";
    const std::string form = j.value("form", "radiance");
    if (form == "radiance") p.form = LayoutForm::Radiance;
    else if (form == "linear_over_pi") p.form = LayoutForm::LinearOverPi;
    else throw file_error(path, "unknown form '" + form + "' (radiance, linear_over_pi)");
    if (p.form == LayoutForm::LinearOverPi && p.coeffs != 4) throw file_error(path, "linear_over_pi holds L0 and L1 only");
    for (const auto& jf : j.at("files")) {
      LayoutFile lf;
      lf.pattern = jf.at("pattern").get<std::string>();
      lf.slices = jf.value("slices", 1);
      lf.needs_float = jf.value("float", false);
      if (lf.slices < 1) throw file_error(path, "slices must be ≥ 1");
      p.files.push_back(lf);
    }
    for (const auto& jc : j.at("coefficients")) {
      LayoutCoefficient c;
      c.file = jc.at("file").get<int>();
      c.slice = jc.value("slice", 0);
      const auto ch = jc.value("channels", std::vector<std::string>{"R", "G", "B"});
      if (ch.size() != 3) throw file_error(path, "channels must name 3 channels (R, G, B order)");
      for (int i = 0; i < 3; ++i) c.channels[i] = ch[size_t(i)];
      const std::string dec = jc.value("decode", "raw");
      if (dec == "ratio") c.ratio = true, c.k = jc.at("k").get<double>();
      else if (dec != "raw") throw file_error(path, "unknown decode '" + dec + "' (raw, ratio)");
      if (c.file < 0 || size_t(c.file) >= p.files.size()) throw file_error(path, "coefficient names a file that does not exist");
      if (c.slice < 0 || c.slice >= p.files[size_t(c.file)].slices) throw file_error(path, "coefficient names a slice that does not exist");
      p.coefficients.push_back(c);
    }
    if (p.coefficients.empty() || int(p.coefficients.size()) > p.coeffs) throw file_error(path, "1..coeffs coefficients expected");
    if (p.coefficients[0].ratio) throw file_error(path, "coefficient 0 (L0) cannot be ratio-encoded");
  } catch (const nlohmann::json::exception& e) {
    throw file_error(path, std::string("malformed layout (") + e.what() + ")");
  }
  return p;
}

std::vector<std::string> list_layouts() { return list_data_files("bakers"); }

ShImage read_layout(const LayoutPreset& layout, const std::string& base, const std::string& normals_path,
                    ReadStats* stats) {
  if (layout.canonical || normals_path.empty()) return read_layout(layout, base, nullptr, stats);
  // Checked before the SH files are decoded, so a bad normal map fails fast.
  const ImageF n = read_image(normals_path);
  if (n.channels < 3) throw file_error(normals_path, "normal map needs 3 channels (X Y Z)");
  LayoutNormals ln{normals_path, n.width, n.height, std::vector<float>(n.texels() * 3), {}};
  for (size_t i = 0; i < n.texels(); ++i)
    for (int a = 0; a < 3; ++a) ln.normals[i * 3 + a] = n.data[i * n.channels + a];
  return read_layout(layout, base, &ln, stats);
}

ShImage read_layout(const LayoutPreset& layout, const std::string& base, const LayoutNormals* normals,
                    ReadStats* stats) {
  if (layout.canonical) return read_canonical_sh(base, stats);
  // Every file of the set, checked before any is decoded.
  struct Loaded {
    std::string path;
    ImageF img;
    std::map<std::string, int> channel;
    int slice_height = 0;
  };
  std::vector<Loaded> files;
  int width = -1, height = -1;
  for (const LayoutFile& lf : layout.files) {
    Loaded l;
    l.path = lf.pattern;
    const size_t at = l.path.find("{base}");
    if (at != std::string::npos) l.path.replace(at, 6, base);
    if (!fs::exists(l.path)) throw file_error(l.path, "file not found (layout " + layout.name + " needs it)");
    ImageFileInfo info;
    l.img = read_image(l.path, &info);
    if (lf.needs_float && !info.is_float)
      throw file_error(l.path, "8-bit data where layout " + layout.name + " needs float (HDR) values");
    if (l.img.height % lf.slices != 0)
      throw file_error(l.path, "height " + std::to_string(l.img.height) + " does not divide into " +
                                   std::to_string(lf.slices) + " stacked layers");
    l.slice_height = l.img.height / lf.slices;
    for (size_t c = 0; c < info.channel_names.size(); ++c) l.channel[info.channel_names[c]] = int(c);
    if (width < 0) width = l.img.width, height = l.slice_height;
    if (l.img.width != width || l.slice_height != height)
      throw file_error(l.path, "layer size " + std::to_string(l.img.width) + "x" + std::to_string(l.slice_height) +
                                   " differs from the set's " + std::to_string(width) + "x" + std::to_string(height));
    files.push_back(std::move(l));
  }
  for (const LayoutCoefficient& c : layout.coefficients)
    for (const std::string& ch : c.channels)
      if (!files[size_t(c.file)].channel.count(ch))
        throw file_error(files[size_t(c.file)].path, "no channel " + ch + " (layout " + layout.name + " reads it)");

  ShImage sh = make_sh_image(width, height, layout.coeffs);
  auto stored = [&](const LayoutCoefficient& c, int x, int y, int ch) {
    const Loaded& l = files[size_t(c.file)];
    return double(l.img.at(x, y + c.slice * l.slice_height)[l.channel.at(c.channels[ch])]);
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* t = sh.texel(size_t(y) * width + x);
      for (int ch = 0; ch < 3; ++ch) {
        const double l0 = stored(layout.coefficients[0], x, y, ch);
        for (size_t k = 0; k < layout.coefficients.size(); ++k) {
          const LayoutCoefficient& c = layout.coefficients[k];
          double v = stored(c, x, y, ch);
          if (c.ratio) v = (v - 0.5) * c.k * l0;
          // To the canonical radiance projection (sh/sh.h): E(n) = π·Y00·c0 + (2π/3)·Y1·c1·n.
          if (layout.form == LayoutForm::LinearOverPi) v = k == 0 ? v / kY00 : 1.5 * v / kY1;
          t[k * 3 + ch] = float(v);
        }
      }
    }
  if (layout.world_space) {
    if (!normals)
      throw file_error(base, "layout " + layout.name + " stores world-space SH: give the lightmap's normals (--normals N.exr)");
    if (normals->width != width || normals->height != height)
      throw file_error(normals->source, "normal map is " + std::to_string(normals->width) + "x" + std::to_string(normals->height) +
                                            ", the lightmap " + std::to_string(width) + "x" + std::to_string(height));
    const bool has_cov = !normals->coverage.empty();
    sh.normals.resize(sh.texels() * 3);
    for (size_t i = 0; i < sh.texels(); ++i) {
      const float* src = &normals->normals[i * 3];
      double v[3] = {src[0], src[1], src[2]};
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (has_cov && !normals->coverage[i]) {  // outside every chart: any unit normal will do
        sh.normals[i * 3 + 0] = 0, sh.normals[i * 3 + 1] = 0, sh.normals[i * 3 + 2] = 1;
        continue;
      }
      if (!(len > 1e-6) || !std::isfinite(len))
        throw file_error(normals->source, "zero-length or non-finite normal at texel (" + std::to_string(i % width) + ", " +
                                              std::to_string(i / width) + ")");
      for (int a = 0; a < 3; ++a) sh.normals[i * 3 + a] = float(v[a] / len);
    }
  }
  ReadStats local;
  const bool given_cov = normals && !normals->coverage.empty() && normals->coverage.size() == sh.texels();
  sanitise_sh(sh, /*derive_coverage=*/!given_cov, stats ? stats : &local);
  if (given_cov)
    for (size_t i = 0; i < sh.texels(); ++i) sh.coverage[i] = sh.coverage[i] && normals->coverage[i];
  return sh;
}

void layout_size(const LayoutPreset& layout, const std::string& base, int* width, int* height) {
  std::string path = layout.canonical ? base : layout.files.at(0).pattern;
  if (const size_t at = path.find("{base}"); !layout.canonical && at != std::string::npos) path.replace(at, 6, base);
  if (!fs::exists(path)) throw file_error(path, "file not found (layout " + layout.name + " needs it)");
  const ImageFileInfo info = read_image_info(path);
  *width = info.width;
  *height = info.height / (layout.canonical ? 1 : std::max(1, layout.files[0].slices));
}

}  // namespace ahd

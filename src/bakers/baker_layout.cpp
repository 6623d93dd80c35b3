#include "bakers/baker_layout.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/parallel.h"
#include "core/json_depth.h"
#include "files/input_file.h"
#include "files/input_record.h"
#include "sh/sh.h"
#include "core/json_number.h"
#include "files/paths.h"
#include "image/colour_space.h"
#include "image/image_io.h"
#include "bakers/layout_pages.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

// A preset's bounds: real ones list at most 9 files and nest 4 levels.
constexpr size_t kMaxLayoutFiles = 64;
constexpr size_t kMaxLayoutJsonDepth = 64;
using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Loading a preset

namespace {

// The preset's own file and what it has parsed so far, to check references against.
struct PresetParse {
  const std::string& path;
  const LayoutPreset& preset;
};

void check_source(const PresetParse& pp, const LayoutSource& s) {
  if (s.file < 0 || size_t(s.file) >= pp.preset.files.size())
    throw file_error(pp.path, "coefficient names a file that does not exist");
  if (s.slice < 0 || s.slice >= pp.preset.files[size_t(s.file)].slices)
    throw file_error(pp.path, "coefficient names a slice that does not exist");
}

LayoutSource parse_source(const PresetParse& pp, const json& j) {
  LayoutSource s{int(json_whole(j.at("file"), 0, 64, pp.path, "file")), int(json_whole_or(j, "slice", 0, 0, 1 << 16, pp.path)),
                 j.at("channel").get<std::string>()};
  check_source(pp, s);
  return s;
}

LayoutFile parse_file(const std::string& path, const json& jf) {
  LayoutFile lf;
  lf.pattern = jf.at("pattern").get<std::string>();
  lf.slices = int(json_whole_or(jf, "slices", 1, 1, 1 << 16, path));
  lf.needs_float = jf.value("float", false);
  lf.part = int(json_whole_or(jf, "part", 0, 0, 1 << 16, path));
  lf.part_name = jf.value("part_name", "");
  lf.per_page = jf.value("per_page", false);
  const std::string encoding = jf.value("encoding", "linear");
  if (encoding != "linear" && encoding != "srgb")
    throw file_error(path, "unknown encoding '" + encoding + "' (linear, srgb)");
  lf.srgb = encoding == "srgb";
  if (lf.slices < 1) throw file_error(path, "slices must be ≥ 1");
  if (lf.part < 0) throw file_error(path, "part must be ≥ 0");
  return lf;
}

// The three per-colour sources: either `sources` (one {file, slice, channel} per colour) or the
// shorthand `file` + `slice` + `channels` (one image, three channel names).
void parse_sources(const PresetParse& pp, const json& jc, LayoutCoefficient& c) {
  if (jc.contains("sources")) {
    if (jc.contains("file") || jc.contains("channels"))
      throw file_error(pp.path, "a coefficient gives either sources or file + channels, not both");
    const json& js = jc.at("sources");
    if (!js.is_array() || js.size() != 3) throw file_error(pp.path, "sources must list 3 sources (R, G, B order)");
    for (size_t i = 0; i < 3; ++i) c.source[i] = parse_source(pp, js[i]);
    return;
  }
  const int file = int(json_whole(jc.at("file"), 0, 64, pp.path, "file")),
            slice = int(json_whole_or(jc, "slice", 0, 0, 1 << 16, pp.path));
  const auto ch = jc.value("channels", std::vector<std::string>{"R", "G", "B"});
  if (ch.size() != 3) throw file_error(pp.path, "channels must name 3 channels (R, G, B order)");
  for (size_t i = 0; i < 3; ++i) c.source[i] = {file, slice, ch[i]};
  check_source(pp, c.source[0]);
}

LayoutCoefficient parse_coefficient(const PresetParse& pp, const json& jc) {
  LayoutCoefficient c;
  parse_sources(pp, jc, c);
  const std::string dec = jc.value("decode", "raw");
  if (dec == "ratio") c.ratio = true, c.k = jc.at("k").get<double>();
  else if (dec != "raw") throw file_error(pp.path, "unknown decode '" + dec + "' (raw, ratio)");
  c.scale = jc.value("scale", 1.0);
  if (jc.contains("divide_by")) {
    c.divided = true;
    c.divisor = parse_source(pp, jc.at("divide_by"));
    c.divisor_min = jc.at("divide_by").value("min", 0.0);
  }
  if (jc.contains("multiply_by")) {  // RGBM: value · range · m^power, m a stored number (alpha)
    const json& jm = jc.at("multiply_by");
    c.multiplied = true;
    c.multiplier = parse_source(pp, jm);
    c.multiplier_scale = jm.value("scale", 1.0);
    c.multiplier_power = jm.value("power", 1.0);
  }
  return c;
}

LayoutForm parse_form(const std::string& path, const std::string& form) {
  if (form == "radiance") return LayoutForm::Radiance;
  if (form == "linear_over_pi") return LayoutForm::LinearOverPi;
  throw file_error(path, "unknown form '" + form + "' (radiance, linear_over_pi)");
}

// "mesh_axes": ["-x", "y", "z"]: each baker axis as a signed glTF axis, each axis used once.
void parse_mesh_axes(const std::string& path, const json& j, LayoutPreset& p) {
  if (!j.contains("mesh_axes")) return;
  const auto axes = j.at("mesh_axes").get<std::vector<std::string>>();
  const std::string bad = "mesh_axes must name x, y and z once each, optionally negated (e.g. [\"-x\", \"y\", \"z\"])";
  if (axes.size() != 3) throw file_error(path, bad);
  bool used[3] = {false, false, false};
  for (int i = 0; i < 3; ++i) {
    std::string a = axes[size_t(i)];
    p.mesh_sign[i] = 1;
    if (!a.empty() && (a[0] == '-' || a[0] == '+')) p.mesh_sign[i] = a[0] == '-' ? -1 : 1, a = a.substr(1);
    if (a.size() != 1 || a[0] < 'x' || a[0] > 'z' || used[a[0] - 'x']) throw file_error(path, bad);
    p.mesh_axis[i] = a[0] - 'x';
    used[p.mesh_axis[i]] = true;
  }
}

void parse_preset(const std::string& path, const json& j, LayoutPreset& p) {
  p.coeffs = int(json_whole(j.at("coeffs"), 0, 9, path, "coeffs"));
  if (!valid_sh_coeffs(p.coeffs)) throw file_error(path, "coeffs must be 1, 4 or 9");
  const std::string space = j.value("space", "tangent");
  if (space != "tangent" && space != "world") throw file_error(path, "space must be tangent or world");
  p.world_space = space == "world";
  parse_mesh_axes(path, j, p);
  p.form = parse_form(path, j.value("form", "radiance"));
  if (p.form == LayoutForm::LinearOverPi && p.coeffs > 4) throw file_error(path, "linear_over_pi holds L0 and L1 only");
  for (const auto& jf : j.at("files")) p.files.push_back(parse_file(path, jf));
  // Each entry is an image read whole: a preset cannot multiply one file into thousands of copies.
  if (p.files.size() > kMaxLayoutFiles)
    throw file_error(path, std::to_string(p.files.size()) + " files, at most " + std::to_string(kMaxLayoutFiles));
  const PresetParse pp{path, p};
  for (const auto& jc : j.at("coefficients")) p.coefficients.push_back(parse_coefficient(pp, jc));
  if (p.coefficients.empty() || int(p.coefficients.size()) > p.coeffs) throw file_error(path, "1..coeffs coefficients expected");
  if (p.coefficients[0].ratio) throw file_error(path, "coefficient 0 (L0) cannot be ratio-encoded");
}

}  // namespace

LayoutPreset load_layout(const std::string& name_or_path) {
  const std::string path = data_file_path("bakers", name_or_path);
  std::error_code ec;
  if (!fs::exists(fs_path(path), ec)) {
    std::string known;
    for (const auto& n : list_layouts()) known += (known.empty() ? "" : ", ") + n;
    throw file_error(path, "unknown layout '" + name_or_path + "' (known: " + known + ")");
  }
  const std::string text = read_input_text(path, InputKind::kText);  // the opener (files/input_file.h)
  if (json_nesting_depth(text.data(), text.size(), kMaxLayoutJsonDepth) > kMaxLayoutJsonDepth)
    throw file_error(path, "malformed layout (JSON nested more than " + std::to_string(kMaxLayoutJsonDepth) + " levels deep)");
  LayoutPreset p;
  try {
    const json j = json::parse(text);
    p.name = j.at("name").get<std::string>();
    p.description = j.value("description", "");
    p.canonical = j.value("reader", "") == "canonical";
    if (!p.canonical) parse_preset(path, j, p);
  } catch (const json::exception& e) {
    throw file_error(path, std::string("malformed layout (") + e.what() + ")");
  }
  return p;
}

std::vector<std::string> list_layouts() { return list_data_files("bakers"); }

// ---------------------------------------------------------------------------------------------
// Reading a baker's files

namespace {

// One image of the set: checked from its header first, decoded once every image has passed.
struct SetImage {
  std::string path;
  int part = 0;
  std::map<std::string, int> channel;
  int width = 0, slice_height = 0;
  int height = 0;  // the whole image's rows (slice_height x layers)
  ImageFileInfo info;  // its header (the colour space it declares)
  ImageF img;
};

std::string expand_pattern(const std::string& pattern, const std::string& base) {
  std::string path = pattern;
  const size_t at = path.find("{base}");
  if (at != std::string::npos) path.replace(at, 6, base);
  return path;
}

// The part index a file entry names (by index, or by name among the file's parts).
int resolve_part(const LayoutFile& lf, const std::string& path, const ImageFileInfo& first) {
  if (lf.part_name.empty()) return lf.part;
  const auto it = std::find(first.parts.begin(), first.parts.end(), lf.part_name);
  if (it != first.parts.end()) return int(it - first.parts.begin());
  std::string known;
  for (const auto& n : first.parts) known += (known.empty() ? "" : ", ") + (n.empty() ? "(unnamed)" : n);
  throw file_error(path, "no part named '" + lf.part_name + "' (parts: " + known + ")");
}

// Header checks of one image: it exists, has the part, holds float data if needed, divides into
// its layers.
SetImage open_image(const LayoutFile& lf, const std::string& base, const std::string& layout) {
  SetImage s;
  s.path = expand_pattern(lf.pattern, base);
  if (!input_exists(s.path)) throw file_error(s.path, "file not found (layout " + layout + " needs it)");
  ImageFileInfo info = read_image_info(s.path);
  s.part = resolve_part(lf, s.path, info);
  if (s.part != 0) info = read_image_info(s.path, s.part);
  if (lf.needs_float && !info.is_float)
    throw file_error(s.path, "8-bit data where layout " + layout + " needs float (HDR) values");
  if (info.height % lf.slices != 0)
    throw file_error(s.path, "height " + std::to_string(info.height) + " does not divide into " +
                                 std::to_string(lf.slices) + " stacked layers");
  s.width = info.width;
  s.height = info.height;
  s.slice_height = info.height / lf.slices;
  for (size_t c = 0; c < info.channel_names.size(); ++c) s.channel[info.channel_names[c]] = int(c);
  s.info = std::move(info);
  return s;
}

void check_sizes(const std::vector<SetImage>& set) {
  const int w = set[0].width, h = set[0].slice_height;
  for (const SetImage& s : set)
    if (s.width != w || s.slice_height != h)
      throw file_error(s.path, "layer size " + std::to_string(s.width) + "x" + std::to_string(s.slice_height) +
                                   " differs from the set's " + std::to_string(w) + "x" + std::to_string(h));
}

void check_channel(const std::vector<SetImage>& set, const LayoutSource& src, const std::string& layout) {
  const SetImage& s = set[size_t(src.file)];
  if (!s.channel.count(src.channel))
    throw file_error(s.path, "no channel " + src.channel + " (layout " + layout + " reads it)");
}

// Every image of the set, checked from its header; no pixel is decoded yet.
std::vector<SetImage> open_set(const LayoutPreset& layout, const std::string& base) {
  std::vector<SetImage> set;
  for (const LayoutFile& lf : layout.files) {
    set.push_back(open_image(lf, base, layout.name));
    // Each entry holds its decoded image: one file (and part) named twice would be held twice.
    for (size_t k = 0; k + 1 < set.size(); ++k)
      if (std::error_code ec; set[k].part == set.back().part &&
                              (set[k].path == set.back().path || fs::equivalent(fs_path(set[k].path), fs_path(set.back().path), ec)))
        throw file_error(set.back().path, "named twice by layout " + layout.name + " (files " + std::to_string(k) +
                                              " and " + std::to_string(set.size() - 1) + "): each file is read once");
  }
  check_sizes(set);
  for (const LayoutCoefficient& c : layout.coefficients) {
    for (const LayoutSource& src : c.source) check_channel(set, src, layout.name);
    if (c.divided) check_channel(set, c.divisor, layout.name);
    if (c.multiplied) check_channel(set, c.multiplier, layout.name);
  }
  return set;
}

// A LayoutSource resolved against the decoded set: the image, channel index and first row, looked up
// once instead of per texel (channel names are strings in a map).
struct Stored {
  const ImageF* img = nullptr;
  int channel = 0, row0 = 0;
  double at(int x, int y) const { return double(img->at(x, y + row0)[channel]); }
};

Stored resolve(const std::vector<SetImage>& set, const LayoutSource& src) {
  const SetImage& s = set[size_t(src.file)];
  return {&s.img, s.channel.at(src.channel), src.slice * s.slice_height};
}

struct ResolvedCoefficient {
  const LayoutCoefficient* c;
  Stored source[3], divisor, multiplier;
};

ResolvedCoefficient resolve(const std::vector<SetImage>& set, const LayoutCoefficient& c) {
  ResolvedCoefficient r{&c, {}, {}, {}};
  for (int i = 0; i < 3; ++i) r.source[i] = resolve(set, c.source[i]);
  if (c.divided) r.divisor = resolve(set, c.divisor);
  if (c.multiplied) r.multiplier = resolve(set, c.multiplier);
  return r;
}

double decode(const ResolvedCoefficient& r, int colour, double l0, int x, int y) {
  const LayoutCoefficient& c = *r.c;
  double v = r.source[colour].at(x, y);
  if (c.ratio) v = (v - 0.5) * c.k * l0;
  v *= c.scale;
  if (c.divided) v /= std::max(c.divisor_min, r.divisor.at(x, y));
  if (c.multiplied) v *= c.multiplier_scale * std::pow(std::max(0.0, r.multiplier.at(x, y)), c.multiplier_power);
  return v;
}

// Decoded stored values → the canonical radiance projection (sh/sh.h): the linear form
// E(n)/π = L0 + L1·n equals (π·Y00·c0 + (2π/3)·Y1·c1·n)/π.
double to_radiance(LayoutForm form, size_t k, double v) {
  if (form == LayoutForm::Radiance) return v;
  return k == 0 ? v / kY00 : 1.5 * v / kY1;
}

// One 3-channel image whose R, G, B are coefficient 0 as stored, up to a scale (plain lightmaps):
// it can be decoded in place, its buffer becoming the SH image's.
bool decodes_in_place(const LayoutPreset& layout, const std::vector<SetImage>& set) {
  if (set.size() != 1 || layout.coeffs != 1 || layout.coefficients.size() != 1) return false;
  if (layout.files.at(0).slices != 1 || set[0].img.channels != 3 || set[0].img.height != set[0].slice_height)
    return false;
  const LayoutCoefficient& c = layout.coefficients[0];
  if (c.ratio || c.divided || c.multiplied) return false;
  for (int i = 0; i < 3; ++i)
    if (c.source[i].file != 0 || c.source[i].slice != 0 || set[0].channel.at(c.source[i].channel) != i) return false;
  return true;
}

// The decoded set as canonical SH. A set that decodes in place gives its image's buffer up (the
// arithmetic is decode()'s, so the values are the same): no second copy of the largest buffer.
ShImage to_canonical(const LayoutPreset& layout, std::vector<SetImage>& set) {
  const int width = set[0].width, height = set[0].slice_height;
  const size_t w = size_t(width);
  if (decodes_in_place(layout, set)) {
    ShImage sh;
    sh.width = width;
    sh.height = height;
    sh.coeffs = 1;
    sh.data = std::move(set[0].img.data);
    assign_large(sh.coverage, sh.texels(), uint8_t(1));
    const double scale = layout.coefficients[0].scale;
    parallel_for(size_t(height), 0, 16, [&](size_t y) {
      for (size_t j = y * w * 3; j < (y + 1) * w * 3; ++j)
        sh.data[j] = float(to_radiance(layout.form, 0, double(sh.data[j]) * scale));
    });
    return sh;
  }
  ShImage sh = make_sh_image(width, height, layout.coeffs);
  std::vector<ResolvedCoefficient> coeffs;
  for (const LayoutCoefficient& c : layout.coefficients) coeffs.push_back(resolve(set, c));
  parallel_for(size_t(height), 0, 16, [&](size_t yy) {
    const int y = int(yy);
    for (int x = 0; x < width; ++x) {
      float* t = sh.texel(size_t(y) * w + size_t(x));
      for (int ch = 0; ch < 3; ++ch) {
        const double l0 = decode(coeffs[0], ch, 0, x, y);  // coefficient 0 is never ratio-encoded
        t[ch] = float(to_radiance(layout.form, 0, l0));
        for (size_t k = 1; k < coeffs.size(); ++k)
          t[k * 3 + ch] = float(to_radiance(layout.form, k, decode(coeffs[k], ch, l0, x, y)));
      }
    }
  });
  return sh;
}

// The set's colour: the primaries its float files declare (one space for the set) or
// layout.input_space, and per file whether its colour planes are sRGB-encoded.
struct SetColour {
  SourceSpace primaries;
  std::vector<bool> srgb;
};

bool same_primaries(const SourceSpace& a, const SourceSpace& b) {
  if (a.working_primaries() || b.working_primaries()) return a.working_primaries() == b.working_primaries();
  return a.name == b.name && a.chromaticities == b.chromaticities;
}

SetColour set_colour(const LayoutPreset& layout, const std::vector<SetImage>& set) {
  SetColour sc;
  if (!layout.input_space.empty()) {  // the user's word replaces every declaration
    sc.primaries = parse_input_space(layout.input_space);
    sc.srgb.assign(set.size(), sc.primaries.srgb_encoded());
    return sc;
  }
  std::string first;
  for (size_t i = 0; i < set.size(); ++i) {
    const SourceSpace d = declared_space(set[i].info, set[i].path);
    sc.srgb.push_back(layout.files[i].srgb || d.srgb_encoded());
    if (!set[i].info.is_float) continue;
    if (first.empty()) {
      sc.primaries = d, first = set[i].path;
    } else if (!same_primaries(d, sc.primaries)) {
      throw file_error(set[i].path, "declares " + d.describe() + " but " + first + " declares " +
                                        sc.primaries.describe() + ": give the set's one space with --input-space");
    }
  }
  return sc;
}

// The (layer, channel) pairs of file `file` that hold colour: coefficient 0's sources, unless a
// ratio-decoded coefficient, a divisor or a multiplier reads them as well (direction, ratio and
// RGBM's alpha are data, never decoded).
std::vector<std::pair<int, std::string>> colour_planes(const LayoutPreset& layout, int file) {
  std::set<std::pair<int, std::string>> colour, data;
  for (size_t k = 0; k < layout.coefficients.size(); ++k) {
    const LayoutCoefficient& c = layout.coefficients[k];
    for (const LayoutSource& src : c.source)
      if (src.file == file) (k == 0 ? colour : data).insert({src.slice, src.channel});
    if (c.divided && c.divisor.file == file) data.insert({c.divisor.slice, c.divisor.channel});
    if (c.multiplied && c.multiplier.file == file) data.insert({c.multiplier.slice, c.multiplier.channel});
  }
  std::vector<std::pair<int, std::string>> out;
  for (const auto& p : colour)
    if (!data.count(p)) out.push_back(p);
  return out;
}

// Decodes file `file`'s colour planes from sRGB to linear, in place (before any decode arithmetic).
void decode_srgb_planes(const LayoutPreset& layout, int file, SetImage& s) {
  for (const auto& [slice, name] : colour_planes(layout, file)) {
    const size_t ch = size_t(s.channel.at(name)), stride = size_t(s.img.channels);
    const size_t first = size_t(slice) * size_t(s.slice_height) * size_t(s.width) * stride;
    srgb_decode(s.img.data.data() + first + ch, size_t(s.slice_height) * size_t(s.width), stride);
  }
}

// Texels outside every chart (given coverage says so) may hold any normal.
bool normal_unused(const LayoutNormals& n, size_t i) { return !n.coverage.empty() && !n.coverage[i]; }

double normal_length(const LayoutNormals& n, size_t i) {
  const float* v = &n.normals[i * 3];
  return std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
}

// World-space layouts need usable normals of the lightmap's size; checked before the SH is decoded.
void check_normals(const LayoutPreset& layout, const std::string& base, const LayoutNormals* normals, const SetImage& first) {
  if (!normals)
    throw file_error(base, "layout " + layout.name + " stores world-space SH: give its normals: --godot-scene S.tscn (a Godot project: the scene whose LightmapGI baked it), --mesh M.glb with its lightmap UVs [+ --placement P.json or the Unity scene for an atlas of instances], or --normals N.exr (a lightmap-space normal EXR)");
  const int w = first.width, h = first.slice_height;
  if (normals->width != w || normals->height != h)
    throw file_error(normals->source, "normal map is " + std::to_string(normals->width) + "x" + std::to_string(normals->height) +
                                          ", the lightmap " + std::to_string(w) + "x" + std::to_string(h));
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    const double len = normal_length(*normals, i);
    if (!normal_unused(*normals, i) && !(len > 1e-6 && std::isfinite(len)))
      throw file_error(normals->source, "zero-length or non-finite normal at texel (" + std::to_string(i % size_t(w)) + ", " +
                                            std::to_string(i / size_t(w)) + ")");
  }
}

void attach_world_normals(ShImage& sh, const LayoutNormals& normals) {
  sh.normals.resize(sh.texels() * 3);
  for (size_t i = 0; i < sh.texels(); ++i) {
    const double len = normal_length(normals, i);
    for (int a = 0; a < 3; ++a)
      sh.normals[i * 3 + a] = normal_unused(normals, i) ? float(a == 2) : float(normals.normals[i * 3 + a] / len);
  }
}

}  // namespace

std::string layout_base(const LayoutPreset& layout, const std::string& input) {
  if (layout.canonical || layout.files.empty()) return input;
  if (probe_input_file(expand_pattern(layout.files[0].pattern, input))) return input;
  // The longest matching suffix first, so "_L1x.tga" is not mistaken for a shorter one.
  std::string best;
  for (const LayoutFile& lf : layout.files) {
    if (lf.pattern.rfind("{base}", 0) != 0) continue;
    const std::string suffix = lf.pattern.substr(6);
    if (suffix.size() > best.size() && input.size() > suffix.size() &&
        input.compare(input.size() - suffix.size(), suffix.size(), suffix) == 0)
      best = suffix;
  }
  return best.empty() ? input : input.substr(0, input.size() - best.size());
}

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
  if (layout.canonical) return read_canonical_sh(base, stats, layout.input_space);
  // A paged layout read without choosing a page must hold exactly one (never mix pages' layers).
  if (layout.page_count == 0 && layout_is_paged(layout)) {
    const LayoutPages lp = layout_pages(layout, base, 0);  // throws when the count is unknown
    if (lp.pages != 1)
      throw file_error(layout_base(layout, base), "holds " + std::to_string(lp.pages) + " atlas pages (" + lp.why +
                                                      "): read one page at a time (layout_page)");
  }
  std::vector<SetImage> set = open_set(layout, layout_base(layout, base));
  if (layout.world_space) check_normals(layout, base, normals, set[0]);
  // A space OpenColorIO cannot convert is refused here, before any pixel is decoded.
  const SetColour colour = set_colour(layout, set);
  const Matrix3 to_working = working_space_matrix(colour.primaries, set[0].path);
  for (SetImage& s : set) {
    ImageFileInfo now;
    s.img = read_image(s.path, &now, s.part);
    // The set was sized and its channels mapped from the headers read above: a file replaced since
    // must not be indexed by them (issue 26).
    if (now.width != s.width || now.height != s.height || s.img.width != s.width || s.img.height != s.height)
      throw file_error(s.path, "changed while it was read (its header differs from a moment ago)");
    for (const auto& [name, index] : s.channel)
      if (size_t(index) >= now.channel_names.size() || now.channel_names[size_t(index)] != name)
        throw file_error(s.path, "changed while it was read (its channels differ from a moment ago)");
  }
  bool decoded = false;
  for (size_t i = 0; i < set.size(); ++i)
    if (colour.srgb[i]) decode_srgb_planes(layout, int(i), set[i]), decoded = true;
  ShImage sh = to_canonical(layout, set);
  // After decoding: the matrix acts on the SH in the source primaries (the working space's sets
  // skip it, their bytes as before).
  if (!colour.primaries.working_primaries()) apply_matrix(sh, to_working);
  if (layout.world_space) attach_world_normals(sh, *normals);
  ReadStats local;
  ReadStats& st = stats ? *stats : local;
  if (decoded || !colour.primaries.working_primaries())
    st.input_space = colour.primaries.working_primaries()
                         ? parse_input_space("srgb").describe()
                         : colour.primaries.describe() + (decoded ? ", sRGB-encoded colour planes" : "");
  const size_t before = st.non_finite_texels;
  const bool given_cov = normals && !normals->coverage.empty() && normals->coverage.size() == sh.texels();
  sanitise_sh(sh, /*derive_coverage=*/!given_cov, &st);
  if (given_cov)
    for (size_t i = 0; i < sh.texels(); ++i) sh.coverage[i] = sh.coverage[i] && normals->coverage[i];
  // The canonical reader's rule (issue 26: an all-NaN or 3e38 set gave exit 0 and a black map).
  check_not_flooded(set[0].path, sh, st.non_finite_texels - before);
  return sh;
}

void layout_size(const LayoutPreset& layout, const std::string& base, int* width, int* height) {
  if (layout.canonical) {
    const ImageFileInfo info = read_image_info(base);
    *width = info.width, *height = info.height;
    return;
  }
  const SetImage first = open_image(layout.files.at(0), layout_base(layout, base), layout.name);  // header checks only
  *width = first.width, *height = first.slice_height;
}

void mesh_normals_to_layout_axes(const LayoutPreset& layout, std::vector<float>* normals) {
  for (size_t i = 0; i + 2 < normals->size(); i += 3) {
    const float g[3] = {(*normals)[i], (*normals)[i + 1], (*normals)[i + 2]};
    for (int a = 0; a < 3; ++a) (*normals)[i + size_t(a)] = float(layout.mesh_sign[a]) * g[layout.mesh_axis[a]];
  }
}

}  // namespace ahd

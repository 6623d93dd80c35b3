#include "bakers/layout_detect.h"

#include <algorithm>
#include <filesystem>
#include <optional>

#include "core/error.h"
#include "files/input_record.h"
#include "bakers/godot/godot_import.h"
#include "image/image_io.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool has(const std::vector<std::string>& v, const std::string& x) { return std::find(v.begin(), v.end(), x) != v.end(); }

std::string file_name(const std::string& p) { return utf8_string(fs_path(p).filename()); }

// The base of a set whose files end with `suffixes`: `input` minus the suffix it ends with, or
// `input` itself when a file of the set exists for it. Empty when neither.
std::string set_base(const std::string& input, const std::vector<std::string>& suffixes) {
  for (const std::string& s : suffixes)
    if (ends_with(input, s)) return input.substr(0, input.size() - s.size());
  for (const std::string& s : suffixes)
    if (probe_input_file(input + s)) return input;
  return "";
}

using Found = std::vector<LayoutDetection>;

// Godot's L1 layers (layers 1..3 of every page): any negative value means raw signed L1 (packed
// values are t = L1/(8·L0) + ½ clamped to [0, 1]). Returns the smallest and largest value.
void godot_l1_range(const std::string& exr, int slices, double* lo, double* hi) {
  const ImageF img = read_image(exr);
  // slices/vertical comes from the .import file: more layers than rows divided by zero (issue 26).
  if (slices <= 0 || img.height % slices != 0)
    throw file_error(exr + ".import", "slices/vertical=" + std::to_string(slices) + " does not divide the " +
                                          std::to_string(img.height) + " rows of " + file_name(exr) + " into layers");
  const int layer_rows = img.height / slices;
  *lo = 1e300, *hi = -1e300;
  for (int y = 0; y < img.height; ++y) {
    if ((y / layer_rows) % 4 == 0) continue;  // an L0 layer
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < std::min(3, img.channels); ++c) {
        const double v = img.at(x, y)[c];
        *lo = std::min(*lo, v), *hi = std::max(*hi, v);
      }
  }
}

void detect_godot(const std::string& input, Found* found) {
  const std::string base = set_base(input, {".exr"});
  if (base.empty()) return;
  const std::string exr = base + ".exr";
  const GodotImport gi = read_godot_import(exr);
  if (!gi.found || gi.importer != "2d_array_texture" || !probe_input_file(exr)) return;
  LayoutDetection d;
  d.base = base;
  const int slices = std::max(1, gi.slices_vertical);
  d.reasons.push_back(file_name(exr) + ".import: importer 2d_array_texture (Godot LightmapGI), slices/vertical=" +
                      std::to_string(slices));
  if (slices % 4 != 0) {
    if (slices != 1)
      throw file_error(exr, "a Godot non-directional atlas of " + std::to_string(slices) +
                                " pages (slices/vertical not a multiple of 4): only one page (plain) is supported");
    d.preset = "plain";
    d.reasons.push_back("one layer: a non-directional lightmap");
    found->push_back(d);
    return;
  }
  std::string project;
  const std::string version = godot_project_version(exr, &project);
  const int version_packs = godot_version_packs_l1(version);
  if (!version.empty())
    d.reasons.push_back(file_name(project) + ": Godot " + version + " (" +
                        (version_packs == 1 ? "4.4+ packs L1" : version_packs == 0 ? "4.0-4.3 store raw L1" : "unknown") + ")");
  const std::vector<std::string> names = godot_resource_names(base + ".lmbake");
  const bool lmbake_packed = has(names, "_uses_packed_directional");
  if (!names.empty())
    d.reasons.push_back(file_name(base + ".lmbake") + ": " +
                        (lmbake_packed ? "has _uses_packed_directional (4.4+ format)" : "no _uses_packed_directional (4.0-4.3 format)"));
  if (probe_input_file(base + "_shadow.png")) d.notes.push_back(file_name(base + "_shadow.png") + " (shadowmask) ignored");
  double lo = 0, hi = 0;
  godot_l1_range(exr, slices, &lo, &hi);
  const bool is_signed = lo < 0;
  char range[96];
  std::snprintf(range, sizeof range, "L1 layers span [%.3g, %.3g]", lo, hi);
  if (is_signed) {
    if (version_packs == 1 || lmbake_packed)
      throw file_error(exr, "ambiguous Godot bake (candidates: godot4-packed, godot4-unpacked): the project says packed L1 but the " +
                                std::string(range) + " (negative: raw); give --layout");
    d.preset = "godot4-unpacked";
    d.reasons.push_back(std::string("contents: ") + range + ", negative values: raw signed L1");
  } else if (version_packs == 1 || lmbake_packed || (version_packs != 0 && hi > 1)) {
    if (hi > 1)
      throw file_error(exr, "ambiguous Godot bake (candidates: godot4-packed, godot4-unpacked): packed L1 expected but the " +
                                std::string(range) + "; give --layout");
    d.preset = "godot4-packed";
    d.reasons.push_back(std::string("contents: ") + range + ", within [0, 1] as packed L1 is");
  } else if (version_packs == 0) {
    d.preset = "godot4-unpacked";
    // Raw L1 without a negative value is also what Godot's denoiser leaves (godotengine/godot#82655):
    // the conversion measures it and warns (pipeline/sh_input_check.h).
    d.reasons.push_back(std::string("contents: ") + range +
                        " (no negative value: raw L1 as the project's version writes it, or L1 clamped by Godot's "
                        "denoiser, which the conversion checks)");
  } else {
    throw file_error(exr, "ambiguous Godot bake (candidates: godot4-packed, godot4-unpacked): " + std::string(range) +
                              ", no project.godot or .lmbake tells the version; give --layout");
  }
  found->push_back(d);
}

void detect_bakery(const std::string& input, Found* found) {
  const std::string base = set_base(input, {"_L0.hdr", "_L1x.tga", "_L1y.tga", "_L1z.tga", "_L1.tga"});
  if (base.empty()) return;
  const bool sh = probe_input_file(base + "_L1x.tga") && probe_input_file(base + "_L1y.tga") && probe_input_file(base + "_L1z.tga");
  const bool mono = probe_input_file(base + "_L1.tga");
  if (!probe_input_file(base + "_L0.hdr") && !sh && !mono) return;
  if (sh && mono)
    throw file_error(input, "ambiguous Bakery set (candidates: bakery-sh, bakery-monosh): both _L1x/_L1y/_L1z.tga and _L1.tga exist; give --layout");
  if (!sh && !mono)
    throw file_error(base + "_L0.hdr", "Bakery L0 without its L1 files (_L1x/_L1y/_L1z.tga for SH, _L1.tga for MonoSH)");
  LayoutDetection d;
  d.base = base;
  d.preset = sh ? "bakery-sh" : "bakery-monosh";
  d.reasons.push_back(file_name(base) + (sh ? "_L0.hdr + _L1x/_L1y/_L1z.tga: Bakery SH" : "_L0.hdr + _L1.tga: Bakery MonoSH"));
  found->push_back(d);
}

void detect_unity(const std::string& input, Found* found) {
  const std::string base = set_base(input, {"_comp_light.exr", "_comp_dir.png", "_comp_shadowmask.png"});
  if (base.empty() || !probe_input_file(base + "_comp_light.exr")) return;
  LayoutDetection d;
  if (probe_input_file(base + "_comp_dir.png")) {
    d.base = base;
    d.preset = "unity-directional";
    d.reasons.push_back(file_name(base) + "_comp_light.exr + _comp_dir.png: Unity directional lightmap");
  } else {
    d.base = base + "_comp_light";
    d.preset = "plain";
    d.reasons.push_back(file_name(base) + "_comp_light.exr without _comp_dir.png: Unity non-directional lightmap");
  }
  if (probe_input_file(base + "_comp_shadowmask.png")) d.notes.push_back(file_name(base) + "_comp_shadowmask.png (shadowmask) ignored");
  found->push_back(d);
}

void detect_per_file_sets(const std::string& input, Found* found) {
  const std::string rgba = set_base(input, {"_r.exr", "_g.exr", "_b.exr"});
  if (!rgba.empty() && probe_input_file(rgba + "_r.exr") && probe_input_file(rgba + "_g.exr") && probe_input_file(rgba + "_b.exr"))
    found->push_back({"three-rgba", rgba, {file_name(rgba) + "_r/_g/_b.exr: one RGBA image per colour"}, {}});
  std::vector<std::string> sh;
  for (int k = 0; k < 9; ++k) sh.push_back("_sh" + std::to_string(k) + ".exr");
  const std::string per = set_base(input, sh);
  if (!per.empty() && probe_input_file(per + "_sh0.exr"))
    found->push_back({"per-coefficient", per, {file_name(per) + "_sh0.exr …: one image per coefficient"}, {}});
}

// The EXR's own channel and part names.
void detect_exr_contents(const std::string& input, Found* found) {
  const std::string exr = probe_regular_file(input) ? input : probe_input_file(input + ".exr") ? input + ".exr" : "";
  if (exr.empty() || !ends_with(exr, ".exr")) return;
  const ImageFileInfo info = read_image_info(exr);
  const std::string base = exr.substr(0, exr.size() - 4);
  if (has(info.channel_names, "sh0.R")) {
    found->push_back({"canonical", exr, {file_name(exr) + ": channels sh0.R … (ahdpack's canonical EXR)"}, {}});
  } else if (has(info.channel_names, "L0.R")) {
    const bool l2 = has(info.channel_names, "L2m2.R");
    found->push_back({l2 ? "exr-layers-l2" : "exr-layers-l1", base,
                      {file_name(exr) + ": layers L0, L1m1, …" + (l2 ? " L2m2 (L2)" : " (L1)")}, {}});
  } else if (has(info.parts, "L0")) {
    const bool l2 = has(info.parts, "L2m2");
    found->push_back({l2 ? "exr-parts-l2" : "exr-parts-l1", base,
                      {file_name(exr) + ": parts L0, L1m1, …" + (l2 ? " L2m2 (L2)" : " (L1)")}, {}});
  }
}

// A lone image that only a plain lightmap explains, asked only when no baker's set matched: an
// EXR whose channels are exactly R, G, B (and A), or a KTX2 texture (an engine's shipped lightmap,
// Bevy's). Issue 42: a user's `convert lightmap.exr` converts without --layout plain, saying why.
void detect_lone_image(const std::string& input, Found* found) {
  if (!probe_regular_file(input)) return;
  if (ends_with(input, ".ktx2")) {
    const ImageFileInfo info = read_image_info(input);
    found->push_back({"plain-ktx2", input.substr(0, input.size() - 5),
                      {file_name(input) + ": a KTX2 texture of " + std::to_string(info.channel_names.size()) +
                       " channels and no baker's files beside it: one plain (non-directional) lightmap"},
                      {}});
    return;
  }
  if (!ends_with(input, ".exr")) return;
  const ImageFileInfo info = read_image_info(input);
  std::vector<std::string> ch = info.channel_names;
  std::sort(ch.begin(), ch.end());
  if (ch != std::vector<std::string>{"B", "G", "R"} && ch != std::vector<std::string>{"A", "B", "G", "R"}) return;
  // Rows a multiple of 4 × the columns: Godot's stacked L0 + L1 layers without their import file,
  // which a plain read would mix (detect_layout's error says to keep NAME.exr.import).
  if (info.width > 0 && info.height % (4 * info.width) == 0) return;
  found->push_back({"plain", input.substr(0, input.size() - 4),
                    {file_name(input) + ": channels " + (ch.size() == 4 ? "R, G, B, A" : "R, G, B") +
                     " only and no baker's files beside it: one plain (non-directional) lightmap (E/pi); another "
                     "layout: give --layout"},
                    {}});
}

}  // namespace

bool is_canonical_sh_file(const std::string& path) {
  if (!probe_regular_file(path)) return false;
  try {
    return has(read_image_info(path).channel_names, "sh0.R");
  } catch (const Error&) {
    return false;
  }
}

std::optional<LayoutDetection> try_detect_layout(const std::string& input) {
  Found found;
  detect_godot(input, &found);
  detect_bakery(input, &found);
  detect_unity(input, &found);
  detect_per_file_sets(input, &found);
  detect_exr_contents(input, &found);
  if (found.empty()) detect_lone_image(input, &found);
  if (found.empty()) return std::nullopt;
  if (found.size() > 1) {
    std::string list;
    for (const auto& d : found) list += (list.empty() ? "" : ", ") + d.preset + " (" + d.reasons.at(0) + ")";
    throw file_error(input, "ambiguous: several layouts fit (" + list + "); give --layout");
  }
  return found[0];
}

LayoutDetection detect_layout(const std::string& input) {
  if (auto d = try_detect_layout(input)) return *d;
  if (!probe_input_file(input)) throw file_error(input, "file not found (and no baker's set named after it)");
  // An image of other channels (a lone RGB EXR is a plain lightmap, detect_lone_image).
  throw file_error(input, "no SH channels and no baker's files beside it that --layout auto recognises "
                          "(a plain lightmap: --layout plain; Godot: keep NAME.exr.import beside it)");
}

std::vector<std::string> auto_detected_layouts() {
  return {"bakery-monosh", "bakery-sh", "canonical", "exr-layers-l1", "exr-layers-l2", "exr-parts-l1", "exr-parts-l2",
          "godot4-packed", "godot4-unpacked", "per-coefficient", "plain", "plain-ktx2", "three-rgba", "unity-directional"};
}

std::string not_a_lightmap_reason(const std::string& path) {
  if (utf8_string(fs_path(path).filename()).rfind("ReflectionProbe-", 0) == 0)
    return "a Unity reflection probe, not a lightmap";
  return "";
}

}  // namespace ahd

#include "pipeline/manifest.h"
#include "pipeline/set_name.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "containers/container.h"
#include "containers/limits.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "core/json_number.h"
#include "pipeline/plane_scale.h"

namespace ahd {

using nlohmann::json;

namespace {

const char* ratio_form_name(RatioForm f) { return f == RatioForm::Rgb ? "rgb" : "luminance"; }

std::string luma_text(const double l[3]) {
  return std::to_string(l[0]) + " " + std::to_string(l[1]) + " " + std::to_string(l[2]);
}

}  // namespace

std::string manifest_to_json(const Manifest& m) {
  json j;
  j["format"] = "ahdpack-manifest";
  j["version"] = m.version;
  j["profile"] = m.profile;
  j["container"] = m.container;
  j["width"] = m.width;
  j["height"] = m.height;
  j["levels"] = m.levels;
  if (m.layers > 1) {
    j["layers"] = m.layers;
    j["layer_content"] = "array layer p holds atlas page p";
  }
  json planes = json::array();
  for (const auto& p : m.planes) {
    planes.push_back({{"name", p.name}, {"file", p.file}, {"format", format_info(p.format).name},
                      {"width", p.width}, {"height", p.height}, {"levels", p.levels}, {"bytes", p.bytes}, {"sha256", p.sha256}});
    if (p.layers > 1) planes.back()["layers"] = p.layers;
  }
  j["planes"] = planes;
  j["directional"] = m.directional;
  j["decode"] = {
      {"model", "I(n) = Ca + max(0, n.d) Cd;  Ca = ratio * Iz;  Cd = (Iz - Ca) / d.z"},
      {"irradiance", "E(n) = integral of L(w) max(0, n.w) dw (no 1/pi)"},
      {"ratio_form", ratio_form_name(m.ratio_form)},
      {"dz_min", m.dz_min},
      {"horizon_rule", "if d.z < dz_min: d.xy *= sqrt(1 - dz_min^2) / |d.xy|, d.z = dz_min"},
      {"luma", {m.luma[0], m.luma[1], m.luma[2]}},
      {"direction_encoding", m.direction_encoding},
      {"direction_frame", m.direction_frame},
      {"iz_scale", m.iz_scale},
  };
  if (!m.directional) j["decode"]["without_direction"] = "no dir/ratio planes: d = (0,0,1), ratio = 1, so I(n) = Iz";
  if (!m.instances.empty()) {  // additive: manifests without a placed scene keep their bytes
    json inst = json::array();
    for (const ManifestInstance& i : m.instances)
      inst.push_back({{"node", i.node},
                      {"page", i.page},
                      {"uv_scale", {i.scale[0], i.scale[1]}},
                      {"uv_offset", {i.offset[0], i.offset[1]}},
                      {"direction_frame", m.direction_frame}});
    j["instances"] = inst;
    j["instance_uv"] = "atlas_uv = uv2 * uv_scale + uv_offset; glTF UV convention (v down, v = 0 is row 0)";
  }
  return j.dump(2) + "\n";
}

Manifest manifest_from_json(const std::string& text, const std::string& path) {
  json j;
  try {
    j = json::parse(text);
  } catch (const std::exception& e) {
    throw file_error(path, std::string("not a JSON manifest (") + e.what() + ")");
  }
  Manifest m;
  try {
    if (j.value("format", "") != "ahdpack-manifest") throw file_error(path, "not an ahdpack manifest");
    m.version = int(json_whole(j.at("version"), 0, 1 << 30, path, "version"));
    if (m.version != kManifestVersion)
      throw file_error(path, "manifest version " + std::to_string(m.version) + " is not supported (this build reads " +
                                 std::to_string(kManifestVersion) + ")");
    m.profile = j.at("profile").get<std::string>();
    m.container = j.at("container").get<std::string>();
    m.width = uint32_t(json_whole(j.at("width"), 0, UINT32_MAX, path, "width"));
    m.height = uint32_t(json_whole(j.at("height"), 0, UINT32_MAX, path, "height"));
    m.levels = uint32_t(json_whole(j.at("levels"), 0, 64, path, "levels"));
    m.layers = uint32_t(json_whole_or(j, "layers", 1, 0, UINT32_MAX, path));
    if (m.layers < 1 || m.layers > 2048) throw file_error(path, "layers must be 1..2048");
    if (m.width == 0 || m.height == 0) throw file_error(path, "manifest size is empty");
    check_image_size(path, m.width, m.height);
    if (m.levels == 0 || m.levels > full_mip_count(m.width, m.height))
      throw file_error(path, "invalid level count " + std::to_string(m.levels));
    if (m.container != "ktx2" && m.container != "dds") throw file_error(path, "unknown container " + m.container);
    const auto& d = j.at("decode");
    const std::string form = d.at("ratio_form").get<std::string>();
    if (form != "rgb" && form != "luminance") throw file_error(path, "unknown ratio_form " + form);
    m.ratio_form = form == "rgb" ? RatioForm::Rgb : RatioForm::Luminance;
    const auto& planes = j.at("planes");
    if (!planes.is_array() || planes.size() > 5) throw file_error(path, "planes must be a list of at most 5");
    std::set<std::string> names, files;
    for (const auto& p : planes) {
      ManifestPlane mp;
      mp.name = p.at("name").get<std::string>();
      if (mp.name != "iz" && mp.name != "dir" && mp.name != "ratio" && mp.name != "dirratio" && mp.name != "coverage")
        throw file_error(path, "unknown plane " + mp.name);
      if (!names.insert(mp.name).second) throw file_error(path, "plane " + mp.name + " listed twice");
      mp.file = p.at("file").get<std::string>();
      // A plain file name beside the manifest: no folders, no hidden or special names.
      if (!is_plain_file_name(mp.file))
        throw file_error(path, "plane file must be a plain name beside the manifest: " + mp.file);
      if (!files.insert(mp.file).second) throw file_error(path, "file " + mp.file + " named by two planes");
      if (!format_from_name(p.at("format").get<std::string>(), &mp.format))
        throw file_error(path, "unknown plane format " + p.at("format").get<std::string>());
      const std::string why = plane_format_problem(mp.name, mp.format, m.ratio_form);
      if (!why.empty()) throw file_error(path, why);
      mp.width = uint32_t(json_whole(p.at("width"), 0, UINT32_MAX, path, "plane width"));
      mp.height = uint32_t(json_whole(p.at("height"), 0, UINT32_MAX, path, "plane height"));
      mp.levels = uint32_t(json_whole(p.at("levels"), 0, 64, path, "plane levels"));
      // The direction and ratio planes may be ceil(W/s) x ceil(H/s) (s = 2, 4) with their own chain.
      const bool side = mp.name == "dir" || mp.name == "ratio" || mp.name == "dirratio";
      const bool scaled_ok = side && side_plane_scale(m.width, m.height, mp.width, mp.height) > 1 &&
                             mp.levels == scaled_plane_levels(m.levels, mp.width, mp.height);
      if (!scaled_ok && (mp.width != m.width || mp.height != m.height || mp.levels != m.levels))
        throw file_error(path, "plane " + mp.name + " is " + std::to_string(mp.width) + "x" + std::to_string(mp.height) +
                                   " with " + std::to_string(mp.levels) + " level(s), the manifest says " +
                                   std::to_string(m.width) + "x" + std::to_string(m.height) + " with " +
                                   std::to_string(m.levels));
      mp.bytes = uint64_t(json_whole(p.at("bytes"), 0, INT64_MAX, path, "plane bytes"));
      mp.sha256 = p.at("sha256").get<std::string>();
      if (mp.sha256.size() != 64 || mp.sha256.find_first_not_of("0123456789abcdef") != std::string::npos)
        throw file_error(path, "plane " + mp.name + " has no valid sha256");
      mp.layers = uint32_t(json_whole_or(p, "layers", 1, 0, UINT32_MAX, path));
      if (mp.layers != m.layers) throw file_error(path, "plane " + mp.name + " has a layer count other than the manifest's");
      m.planes.push_back(mp);
    }
    m.directional = j.value("directional", true);
    auto has = [&](const char* name) {
      for (const auto& p : m.planes)
        if (p.name == name) return true;
      return false;
    };
    if (!has("iz")) throw file_error(path, "manifest has no iz plane");
    if (m.directional && !has("dirratio") && !(has("dir") && has("ratio")))
      throw file_error(path, "directional manifest lacks its direction/ratio planes");
    if (m.directional && has("dirratio") && (has("dir") || has("ratio")))
      throw file_error(path, "manifest has both dirratio and dir/ratio planes");
    if (!m.directional && (has("dir") || has("ratio") || has("dirratio")))
      throw file_error(path, "a non-directional manifest has direction or ratio planes");
    m.dz_min = d.at("dz_min").get<double>();
    for (int i = 0; i < 3; ++i) m.luma[i] = d.at("luma").at(size_t(i)).get<double>();
    const std::string why = fit_parameters_problem(m.dz_min, m.luma);
    if (!why.empty()) throw file_error(path, why);
    m.direction_encoding = d.at("direction_encoding").get<std::string>();
    m.direction_frame = d.at("direction_frame").get<std::string>();
    m.iz_scale = d.value("iz_scale", 1.0);
    if (!(m.iz_scale > 0 && std::isfinite(m.iz_scale))) throw file_error(path, "iz_scale must be a finite positive number");
    if (j.contains("instances")) {
      const auto& inst = j.at("instances");
      if (!inst.is_array() || inst.size() > 1000000) throw file_error(path, "instances must be a list");
      for (const auto& e : inst) {
        ManifestInstance mi;
        mi.node = e.at("node").get<std::string>();
        mi.page = int(json_whole(e.at("page"), 0, int64_t(m.layers) - 1, path, "instance page"));
        for (int k = 0; k < 2; ++k) {
          mi.scale[k] = e.at("uv_scale").at(size_t(k)).get<double>();
          mi.offset[k] = e.at("uv_offset").at(size_t(k)).get<double>();
          if (!std::isfinite(mi.scale[k]) || !std::isfinite(mi.offset[k]))
            throw file_error(path, "instance " + mi.node + " has a non-finite uv_scale or uv_offset");
        }
        m.instances.push_back(std::move(mi));
      }
    }
  } catch (const json::exception& e) {
    throw file_error(path, std::string("malformed manifest (") + e.what() + ")");
  }
  return m;
}

std::string fit_parameters_problem(double dz_min, const double luma[3]) {
  if (!(dz_min > 0 && dz_min < 1)) return "dz_min must be in (0, 1)";
  for (int i = 0; i < 3; ++i)
    if (!(luma[i] >= 0 && luma[i] <= 1)) return "luma weights must be in [0, 1]";
  if (!(luma[0] + luma[1] + luma[2] > 0)) return "luma weights must not all be 0";
  return "";
}

std::string plane_format_problem(const std::string& role, PixelFormat f, RatioForm form) {
  const FormatInfo& fi = format_info(f);
  const bool hdr = role == "iz";
  const int rgb = form == RatioForm::Rgb ? 2 : 0;  // the RGB ratio takes 3 channels instead of 1
  const int need = role == "iz" ? 3 : role == "dir" ? 2 : role == "ratio" ? 1 + rgb : role == "coverage" ? 1 : 3 + rgb;
  if (role != "iz" && role != "dir" && role != "ratio" && role != "dirratio" && role != "coverage")
    return "unknown plane " + role;
  if (fi.is_float != hdr)
    return std::string("plane ") + role + " cannot be " + fi.name + " (" + (hdr ? "needs an HDR float format" : "needs a UNORM format") + ")";
  if (fi.channels < need)
    return std::string("plane ") + role + " cannot be " + fi.name + " (" + std::to_string(fi.channels) + " channel(s), needs " +
           std::to_string(need) + ")";
  return "";
}

namespace {
// "1" for the default (the bytes every earlier set carries), else the shortest exact decimal.
std::string iz_scale_text(double v) {
  if (v == 1.0) return "1";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
}  // namespace

std::vector<std::pair<std::string, std::string>> plane_metadata(const Manifest& m, const std::string& plane) {
  return {
      {"ahd.version", std::to_string(m.version)},
      {"ahd.plane", plane},
      {"ahd.profile", m.profile},
      {"ahd.ratio_form", ratio_form_name(m.ratio_form)},
      {"ahd.dz_min", std::to_string(m.dz_min)},
      {"ahd.luma", luma_text(m.luma)},
      {"ahd.direction", m.direction_encoding + " " + m.direction_frame},
      {"ahd.iz_scale", iz_scale_text(m.iz_scale)},
      {"ahd.directional", m.directional ? "1" : "0"},
  };
}

bool is_plain_file_name(const std::string& s) {
  return !s.empty() && s[0] != '.' && s.find_first_of(std::string("/\\:\0", 4)) == std::string::npos;
}

std::string set_name_problem(const std::string& name) {
  if (!is_plain_file_name(name) || !is_plain_file_name(name + ".json"))
    return "would make file names decode refuses (it must not be empty, start with '.' or hold '/', '\\' or ':')";
  for (char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "holds a control character (a line break, a tab)";
  if (name.size() > kMaxSetNameBytes)
    return "is " + std::to_string(name.size()) + " bytes long (at most " + std::to_string(kMaxSetNameBytes) + ")";
  const std::string report = ".report";
  if (name.size() >= report.size() && name.compare(name.size() - report.size(), report.size(), report) == 0)
    return "ends in \".report\": its manifest would be the report of the set named without it";
  return "";
}

}  // namespace ahd

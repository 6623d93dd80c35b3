#include "pipeline/manifest.h"

#include <nlohmann/json.hpp>

#include "core/error.h"

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
                      {"width", p.width}, {"height", p.height}, {"levels", p.levels}, {"bytes", p.bytes}});
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
      {"iz_scale", 1.0},
  };
  if (!m.directional) j["decode"]["without_direction"] = "no dir/ratio planes: d = (0,0,1), ratio = 1, so I(n) = Iz";
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
    m.version = j.at("version").get<int>();
    if (m.version != kManifestVersion)
      throw file_error(path, "manifest version " + std::to_string(m.version) + " is not supported (this build reads " +
                                 std::to_string(kManifestVersion) + ")");
    m.profile = j.at("profile").get<std::string>();
    m.container = j.at("container").get<std::string>();
    m.width = j.at("width").get<uint32_t>();
    m.height = j.at("height").get<uint32_t>();
    m.levels = j.at("levels").get<uint32_t>();
    m.layers = j.value("layers", 1u);
    if (m.layers < 1) throw file_error(path, "layers must be at least 1");
    for (const auto& p : j.at("planes")) {
      ManifestPlane mp;
      mp.name = p.at("name").get<std::string>();
      mp.file = p.at("file").get<std::string>();
      if (mp.file.find("..") != std::string::npos || (!mp.file.empty() && mp.file[0] == '/'))
        throw file_error(path, "plane file must be a plain name beside the manifest: " + mp.file);
      if (!format_from_name(p.at("format").get<std::string>(), &mp.format))
        throw file_error(path, "unknown plane format " + p.at("format").get<std::string>());
      mp.width = p.at("width").get<uint32_t>();
      mp.height = p.at("height").get<uint32_t>();
      mp.levels = p.at("levels").get<uint32_t>();
      mp.bytes = p.at("bytes").get<uint64_t>();
      mp.layers = p.value("layers", 1u);
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
    const auto& d = j.at("decode");
    m.ratio_form = d.at("ratio_form").get<std::string>() == "rgb" ? RatioForm::Rgb : RatioForm::Luminance;
    m.dz_min = d.at("dz_min").get<double>();
    if (!(m.dz_min > 0 && m.dz_min < 1)) throw file_error(path, "dz_min must be in (0, 1)");
    for (int i = 0; i < 3; ++i) m.luma[i] = d.at("luma").at(size_t(i)).get<double>();
    m.direction_encoding = d.at("direction_encoding").get<std::string>();
    m.direction_frame = d.at("direction_frame").get<std::string>();
  } catch (const json::exception& e) {
    throw file_error(path, std::string("malformed manifest (") + e.what() + ")");
  }
  return m;
}

std::vector<std::pair<std::string, std::string>> plane_metadata(const Manifest& m, const std::string& plane) {
  return {
      {"ahd.version", std::to_string(m.version)},
      {"ahd.plane", plane},
      {"ahd.profile", m.profile},
      {"ahd.ratio_form", ratio_form_name(m.ratio_form)},
      {"ahd.dz_min", std::to_string(m.dz_min)},
      {"ahd.luma", luma_text(m.luma)},
      {"ahd.direction", m.direction_encoding + " " + m.direction_frame},
      {"ahd.iz_scale", "1"},
      {"ahd.directional", m.directional ? "1" : "0"},
  };
}

}  // namespace ahd

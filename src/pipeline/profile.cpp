#include "pipeline/profile.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace ahd {
namespace fs = std::filesystem;

Profile load_profile(const std::string& name_or_path) {
  const std::string path = data_file_path("profiles", name_or_path);
  std::ifstream f(path);
  if (!f) {
    std::string known;
    for (const auto& n : list_profiles()) known += (known.empty() ? "" : ", ") + n;
    throw file_error(path, "unknown profile '" + name_or_path + "' (known: " + known + ")");
  }
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(f);
  } catch (const std::exception& e) {
    throw file_error(path, std::string("invalid JSON (") + e.what() + ")");
  }
  Profile p;
  auto format = [&](const char* plane) {
    const std::string name = j["planes"][plane].get<std::string>();
    PixelFormat fmt;
    if (!format_from_name(name, &fmt)) throw file_error(path, "unknown format '" + name + "' for plane " + plane);
    return fmt;
  };
  try {
    p.name = j.at("name").get<std::string>();
    p.description = j.value("description", "");
    const std::string form = j.value("ratio_form", "luminance");
    if (form != "luminance" && form != "rgb") throw file_error(path, "ratio_form must be 'luminance' or 'rgb'");
    p.ratio_rgb = form == "rgb";
    const auto& planes = j.at("planes");
    p.iz = format("iz");
    if (planes.contains("dirratio")) {
      p.packed_dir_ratio = true;
      p.dirratio = format("dirratio");
      if (p.dirratio != PixelFormat::RGBA8_UNORM) throw file_error(path, "the packed dirratio plane must be rgba8");
    } else {
      p.dir = format("dir");
      p.ratio = format("ratio");
    }
  } catch (const nlohmann::json::exception& e) {
    throw file_error(path, std::string("malformed profile (") + e.what() + ")");
  }
  if (format_info(p.iz).channels < 3 || !format_info(p.iz).is_float)
    throw file_error(path, "the iz plane needs an HDR RGB format");
  return p;
}

std::vector<std::string> list_profiles() { return list_data_files("profiles"); }

}  // namespace ahd

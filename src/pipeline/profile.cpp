#include "pipeline/profile.h"

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "pipeline/builtin_profiles.h"
#include "pipeline/manifest.h"

namespace ahd {

Profile profile_from_json(const std::string& text, const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
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
    if (j.contains("dir_ratio_scale")) {
      const auto& s = j.at("dir_ratio_scale");
      if (!s.is_number_integer() || (s.get<int64_t>() != 1 && s.get<int64_t>() != 2 && s.get<int64_t>() != 4))
        throw file_error(path, "dir_ratio_scale must be 1, 2 or 4");
      p.dir_ratio_scale = int(s.get<int64_t>());
    }
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
  // decode's own rule for every plane (plane_format_problem): a profile that passes writes a set
  // decode reads back (issue 26: "dir": "r8" read past the plane, "dir": "bc6h" wrote a set decode refused).
  const RatioForm form = p.ratio_rgb ? RatioForm::Rgb : RatioForm::Luminance;
  const std::vector<std::pair<const char*, PixelFormat>> planes =
      p.packed_dir_ratio ? std::vector<std::pair<const char*, PixelFormat>>{{"iz", p.iz}, {"dirratio", p.dirratio}}
                         : std::vector<std::pair<const char*, PixelFormat>>{{"iz", p.iz}, {"dir", p.dir}, {"ratio", p.ratio}};
  for (const auto& [role, fmt] : planes) {
    const std::string why = plane_format_problem(role, fmt, form);
    if (!why.empty()) throw file_error(path, why);
  }
  return p;
}

Profile builtin_profile(const std::string& name) {
  for (size_t i = 0; i < kBuiltinProfileCount; ++i)
    if (name == kBuiltinProfiles[i].name)
      return profile_from_json(kBuiltinProfiles[i].json, "built-in profile " + name);
  std::string known;
  for (const std::string& n : builtin_profile_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown profile '" + name + "' (known: " + known + ")");
}

std::vector<std::string> builtin_profile_names() {
  std::vector<std::string> names;
  for (size_t i = 0; i < kBuiltinProfileCount; ++i) names.push_back(kBuiltinProfiles[i].name);
  return names;  // generated in sorted order
}

}  // namespace ahd

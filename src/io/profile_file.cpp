#include "io/profile_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/paths.h"
#include "io/input_record.h"

namespace ahd {

Profile load_profile(const std::string& name_or_path) {
  const std::string path = data_file_path("profiles", name_or_path);
  std::ifstream f(path);
  if (!f) {
    const bool is_path = std::filesystem::path(name_or_path).extension() == ".json";
    if (!is_path) {
      for (const std::string& n : builtin_profile_names())
        if (n == name_or_path) return builtin_profile(n);
    }
    std::string known;
    for (const auto& n : list_profiles()) known += (known.empty() ? "" : ", ") + n;
    throw file_error(path, "unknown profile '" + name_or_path + "' (known: " + known + ")");
  }
  note_input_file(path);
  std::stringstream text;
  text << f.rdbuf();
  return profile_from_json(text.str(), path);
}

std::vector<std::string> list_profiles() {
  std::vector<std::string> names = list_data_files("profiles");
  return names.empty() ? builtin_profile_names() : names;
}

}  // namespace ahd

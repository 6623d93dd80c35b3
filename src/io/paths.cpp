#include "io/paths.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace ahd {

std::string formats_dir() {
  if (const char* env = std::getenv("AHD_FORMATS_DIR"); env && *env) return env;
  return AHD_FORMATS_DIR;
}

std::string data_file_path(const std::string& folder, const std::string& name_or_path) {
  if (std::filesystem::path(name_or_path).extension() == ".json") return name_or_path;
  return formats_dir() + "/" + folder + "/" + name_or_path + ".json";
}

std::vector<std::string> list_data_files(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(formats_dir() + "/" + folder, ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace ahd

#include "files/profile_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "files/file_io.h"
#include "files/paths.h"
#include "files/utf8_path.h"

namespace ahd {

Profile load_profile(const std::string& name_or_path) {
  const std::string path = data_file_path("profiles", name_or_path);
  std::error_code ec;
  if (!std::filesystem::exists(fs_path(path), ec)) {
    const bool is_path = fs_path(name_or_path).extension() == ".json";
    if (!is_path) {
      for (const std::string& n : builtin_profile_names())
        if (n == name_or_path) return builtin_profile(n);
    }
    std::string known;
    for (const auto& n : list_profiles()) known += (known.empty() ? "" : ", ") + n;
    throw file_error(path, "unknown profile '" + name_or_path + "' (known: " + known + ")");
  }
  // Bounded, regular files only (--profile /dev/zero read without end before, issue 26).
  return profile_from_json(read_text_file(path), path);
}

std::vector<std::string> list_profiles() {
  std::vector<std::string> names = list_data_files("profiles");
  return names.empty() ? builtin_profile_names() : names;
}

}  // namespace ahd

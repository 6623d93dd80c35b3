#include "files/paths.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "files/os_files.h"
#include "files/utf8_path.h"

namespace ahd {

std::string executable_prefix() {
  const std::filesystem::path exe = fs_path(os::executable_path());
  if (exe.empty()) return {};
  std::filesystem::path prefix = exe.parent_path();
  for (const auto& part : std::filesystem::path(AHD_INSTALL_BINDIR))
    if (!part.empty() && part != ".") prefix = prefix.parent_path();
  return utf8_string(prefix);
}

std::string library_prefix() {
  const std::string file = os::module_path_of(reinterpret_cast<const void*>(&library_prefix));
  if (file.empty()) return {};
  std::filesystem::path prefix = fs_path(file).parent_path();
  for (const auto& part : std::filesystem::path(AHD_INSTALL_LIBDIR))
    if (!part.empty() && part != ".") prefix = prefix.parent_path();
  return utf8_string(prefix);
}

namespace {

// The installed data beside the running executable: <prefix>/share/ahdpack/formats for
// <prefix>/bin/ahdpack, else beside the library holding this code. Empty when there is none (a
// build tree, or no /proc).
std::string installed_formats_dir() {
  for (const std::string& prefix : {executable_prefix(), library_prefix()}) {
    if (prefix.empty()) continue;
    std::error_code ec;
    const std::filesystem::path dir = fs_path(prefix) / AHD_INSTALL_FORMATS_DIR;
    if (std::filesystem::is_directory(dir / "profiles", ec)) return utf8_string(dir);
  }
  return {};
}

}  // namespace

std::string formats_dir() {
  if (const char* env = std::getenv("AHD_FORMATS_DIR"); env && *env) return env;
  static const std::string installed = installed_formats_dir();
  return installed.empty() ? AHD_FORMATS_DIR : installed;
}

std::string data_file_path(const std::string& folder, const std::string& name_or_path) {
  if (fs_path(name_or_path).extension() == ".json") return name_or_path;
  return formats_dir() + "/" + folder + "/" + name_or_path + ".json";
}

std::vector<std::string> list_data_files(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(fs_path(formats_dir() + "/" + folder), ec))
    if (e.path().extension() == ".json") names.push_back(utf8_string(e.path().stem()));
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace ahd

#include "files/modules.h"

#include <filesystem>
#include <vector>

#include "core/error.h"
#include "files/os_files.h"
#include "files/paths.h"
#include "files/utf8_path.h"

#ifndef AHD_INSTALL_MODULE_DIR
#define AHD_INSTALL_MODULE_DIR "lib/ahdpack"
#endif

namespace ahd {

namespace {

std::string module_file_name(const std::string& name) {
#ifdef _WIN32
  return "libahd_" + name + ".dll";
#else
  return "libahd_" + name + ".so";
#endif
}

std::string module_path(const std::string& file_name) {
  std::error_code ec;
  for (const std::string& prefix : {executable_prefix(), library_prefix()}) {
    if (prefix.empty()) continue;
    const std::filesystem::path installed = fs_path(prefix) / AHD_INSTALL_MODULE_DIR / fs_path(file_name);
    if (std::filesystem::exists(installed, ec)) return utf8_string(installed);
  }
  std::vector<std::filesystem::path> beside;
  const std::filesystem::path exe = fs_path(os::executable_path());
  if (!exe.empty()) beside.push_back(exe.parent_path() / fs_path(file_name));
  const std::string file = os::module_path_of(reinterpret_cast<const void*>(&module_file_name));
  if (!file.empty()) beside.push_back(std::filesystem::absolute(fs_path(file), ec).parent_path() / fs_path(file_name));
  for (const std::filesystem::path& p : beside)
    if (std::filesystem::exists(p, ec)) return utf8_string(p);
  return beside.empty() ? file_name : utf8_string(beside.front());
}

}  // namespace

LoadedModule load_module_table(const std::string& name, int abi) {
  LoadedModule l;
  l.path = module_path(module_file_name(name));
  void* so = os::load_module(l.path, &l.error);  // files/os_files.h: dlopen, LoadLibraryExW
  if (!so) return l;
  using Entry = const void* (*)();
  const std::string symbol = "ahd_" + name + "_module";
  auto entry = reinterpret_cast<Entry>(os::module_symbol(so, symbol.c_str()));
  const void* table = entry ? entry() : nullptr;
  if (!table || *static_cast<const int*>(table) != abi) {
    l.error = l.path + ": not the " + name + " module of this ahdpack build";
    return l;
  }
  l.table = table;
  return l;
}

const void* module_table(const LoadedModule& loaded, const std::string& why, const char* dependency) {
  if (!loaded.table)
    throw Error(why + ": needs " + dependency + ", whose module cannot be loaded (" + loaded.error + ")");
  return loaded.table;
}

}  // namespace ahd

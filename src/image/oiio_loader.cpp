#include <filesystem>
#include <mutex>
#include <vector>

#include "core/error.h"
#include "image/oiio_module.h"
#include "files/os_files.h"
#include "files/paths.h"
#include "files/utf8_path.h"

#ifdef AHD_NO_OIIO_MODULE
#define AHD_INSTALL_OIIO_MODULE "libahd_oiio.so"  // never opened: load() stops first
#endif

namespace ahd {

namespace {

// Where the module is, relative to the running code only (never a path compiled in: a relocated or
// copied binary must not load whatever a build folder holds at that path now, issue 44):
//  1. installed: <prefix>/<libdir>/ahdpack/libahd_oiio.so for <prefix>/<bindir>/ahdpack, or for
//     <prefix>/<libdir>/libahd_bakers.so (the install's relative layout, as files/paths.cpp finds
//     formats/);
//  2. beside the executable, then beside the library holding this code (the build tree: CMake puts
//     the module beside ahdpack and copies it beside the test binaries).
// The first that exists; else the executable's neighbour, so the error names where it was looked for.
std::string module_path() {
  std::error_code ec;
  for (const std::string& prefix : {executable_prefix(), library_prefix()}) {
    if (prefix.empty()) continue;
    const std::filesystem::path installed = fs_path(prefix) / AHD_INSTALL_OIIO_MODULE;
    if (std::filesystem::exists(installed, ec)) return utf8_string(installed);
  }
  const std::string name = utf8_string(std::filesystem::path(AHD_INSTALL_OIIO_MODULE).filename());
  std::vector<std::filesystem::path> beside;
  const std::filesystem::path exe = fs_path(os::executable_path());
  if (!exe.empty()) beside.push_back(exe.parent_path() / fs_path(name));
  const std::string file = os::module_path_of(reinterpret_cast<const void*>(&module_path));
  if (!file.empty()) beside.push_back(std::filesystem::absolute(fs_path(file), ec).parent_path() / fs_path(name));
  for (const std::filesystem::path& p : beside)
    if (std::filesystem::exists(p, ec)) return utf8_string(p);
  return beside.empty() ? name : utf8_string(beside.front());
}

struct Loaded {
  const OiioModule* module = nullptr;
  std::string path, error;
};

Loaded load() {
  Loaded l;
#ifdef AHD_NO_OIIO_MODULE
  l.error = "this ahdpack was built without it: AHD_OIIO_MODULE=OFF; EXR inputs are read without it";
  return l;
#endif
  l.path = module_path();
  void* so = os::load_module(l.path, &l.error);  // files/os_files.h: dlopen, LoadLibraryExW
  if (!so) return l;
  using Entry = const OiioModule* (*)();
  auto entry = reinterpret_cast<Entry>(os::module_symbol(so, "ahd_oiio_module"));
  const OiioModule* m = entry ? entry() : nullptr;
  if (!m || m->abi != kOiioModuleAbi) {
    l.error = l.path + ": not the OpenImageIO module of this ahdpack build";
    return l;
  }
  l.module = m;
  return l;
}

}  // namespace

const OiioModule& oiio_module(const std::string& why) {
  static const Loaded loaded = load();  // once, thread safe; a failure is remembered
  if (!loaded.module) throw Error(why + ": needs OpenImageIO, whose module cannot be loaded (" + loaded.error + ")");
  return *loaded.module;
}

}  // namespace ahd

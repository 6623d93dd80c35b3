#include <dlfcn.h>

#include <filesystem>
#include <mutex>

#include "core/error.h"
#include "image/oiio_module.h"
#include "files/paths.h"

namespace ahd {

namespace {

// The installed module: <prefix>/<libdir>/ahdpack/libahd_oiio.so for <prefix>/<bindir>/ahdpack, or
// for <prefix>/<libdir>/libahd_bakers.so (the install's relative layout, as files/paths.cpp finds
// formats/), else the build tree's.
std::string module_path() {
  for (const std::string& prefix : {executable_prefix(), library_prefix()}) {
    if (prefix.empty()) continue;
    std::error_code ec;
    const std::filesystem::path installed = std::filesystem::path(prefix) / AHD_INSTALL_OIIO_MODULE;
    if (std::filesystem::exists(installed, ec)) return installed.string();
  }
  return AHD_BUILD_OIIO_MODULE;
}

struct Loaded {
  const OiioModule* module = nullptr;
  std::string path, error;
};

Loaded load() {
  Loaded l;
  l.path = module_path();
  // RTLD_LOCAL: OpenImageIO's symbols stay out of the process's global scope.
  void* so = ::dlopen(l.path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!so) {
    const char* e = ::dlerror();  // names the path
    l.error = e ? e : l.path + ": cannot load";
    return l;
  }
  using Entry = const OiioModule* (*)();
  auto entry = reinterpret_cast<Entry>(::dlsym(so, "ahd_oiio_module"));
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

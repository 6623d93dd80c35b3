// assimp_module (scene/assimp_module.h): libahd_assimp loaded once, or, built with
// AHD_ASSIMP_MODULE=OFF, the same table from the module's code linked in.
#include <string>

#include "files/modules.h"
#include "scene/assimp_module.h"

#ifdef AHD_ASSIMP_BUILTIN
extern "C" const void* ahd_assimp_module();  // src/assimp/module.cpp, linked in
#endif

namespace ahd {

namespace {

LoadedModule load() {
#ifdef AHD_ASSIMP_BUILTIN
  LoadedModule l;
  l.table = ahd_assimp_module();  // compiled into this build: its ABI is this build's
  return l;
#else
  return load_module_table("assimp", kAssimpModuleAbi);  // files/modules.h: where it is looked for
#endif
}

}  // namespace

const AssimpModule& assimp_module(const std::string& why) {
  static const LoadedModule loaded = load();  // once, thread safe; a failure is remembered
  return *static_cast<const AssimpModule*>(module_table(loaded, why, "Assimp"));
}

}  // namespace ahd

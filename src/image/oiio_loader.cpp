#include <string>

#include "files/modules.h"
#include "image/oiio_module.h"

namespace ahd {

namespace {

LoadedModule load() {
#ifdef AHD_NO_OIIO_MODULE
  LoadedModule l;
  l.error = "this ahdpack was built without it: AHD_OIIO_MODULE=OFF; EXR inputs are read without it";
  return l;
#else
  return load_module_table("oiio", kOiioModuleAbi);  // files/modules.h: where it is looked for
#endif
}

}  // namespace

const OiioModule& oiio_module(const std::string& why) {
  static const LoadedModule loaded = load();  // once, thread safe; a failure is remembered
  return *static_cast<const OiioModule*>(module_table(loaded, why, "OpenImageIO"));
}

}  // namespace ahd

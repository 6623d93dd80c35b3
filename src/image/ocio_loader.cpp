#include <string>

#include "files/modules.h"
#include "image/ocio_module.h"

namespace ahd {

const OcioModule& ocio_module(const std::string& why) {
  static const LoadedModule loaded = load_module_table("ocio", kOcioModuleAbi);  // once, thread safe
  return *static_cast<const OcioModule*>(module_table(loaded, why, "OpenColorIO"));
}

}  // namespace ahd

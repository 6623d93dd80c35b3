#include <string>

#include "core/error.h"
#include "files/modules.h"
#include "image/ocio_module.h"

namespace ahd {

const OcioModule& ocio_module(const std::string& why) {
  static const LoadedModule loaded = load_module_table("ocio", kOcioModuleAbi);  // once, thread safe
  if (!loaded.table) throw Error(why + ": needs OpenColorIO, whose module cannot be loaded (" + loaded.error + ")");
  return *static_cast<const OcioModule*>(loaded.table);
}

}  // namespace ahd

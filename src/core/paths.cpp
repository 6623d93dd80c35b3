#include "core/paths.h"

#include <cstdlib>

namespace ahd {

std::string formats_dir() {
  if (const char* env = std::getenv("AHD_FORMATS_DIR"); env && *env) return env;
  return AHD_FORMATS_DIR;
}

}  // namespace ahd

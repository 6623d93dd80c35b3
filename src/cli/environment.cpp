#include "cli/environment.h"

#include <cstdlib>

#include "containers/limits.h"

namespace ahd::cli {

void apply_size_limit_from_environment() {
  const char* s = std::getenv("AHDPACK_MAX_SIZE");
  if (!s || !*s) return;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s, &end, 10);
  if (*end != '\0' || v == 0 || v > 0xFFFFFFFFull) return;
  set_max_image_size(uint32_t(v));
}

}  // namespace ahd::cli

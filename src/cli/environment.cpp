#include "cli/environment.h"

#include <cstdlib>
#include <string>

#include "containers/limits.h"
#include "core/cpu.h"
#include "core/error.h"

namespace ahd::cli {

void apply_size_limit_from_environment() {
  const char* s = std::getenv("AHDPACK_MAX_SIZE");
  if (!s || !*s) return;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s, &end, 10);
  // A typo must not pass unnoticed (the user meant to change the limit): one error line.
  if (*end != '\0' || !(*s >= '0' && *s <= '9') || v == 0 || v > 0xFFFFFFFFull)
    throw Error(std::string("AHDPACK_MAX_SIZE is '") + s +
                "', not a whole number from 1 to 4294967295 (the largest width and height of a level)");
  set_max_image_size(uint32_t(v));
}

void apply_cpu_disable_from_environment() {
  const char* s = std::getenv("AHD_CPU_DISABLE");
  if (!s || !*s) return;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s, &end, 10);
  if (*end != '\0' || !(*s >= '0' && *s <= '9') || v > cpu::kAllSimd)
    throw Error(std::string("AHD_CPU_DISABLE is '") + s + "', not a mask from 0 to " +
                std::to_string(cpu::kAllSimd) + " (a test hook: src/cli/environment.h)");
  cpu::disable_for_tests(unsigned(v));
}

}  // namespace ahd::cli

#include "containers/limits.h"

#include <atomic>
#include <cstdlib>

#include "core/error.h"

namespace ahd {
namespace {

std::atomic<uint32_t> g_override{0};

uint32_t from_environment() {
  const char* s = std::getenv("AHDPACK_MAX_SIZE");
  if (!s || !*s) return kDefaultMaxImageSize;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s, &end, 10);
  // A malformed value must not silently lift the limit: fall back to the default.
  if (*end != '\0' || v == 0 || v > 0xFFFFFFFFull) return kDefaultMaxImageSize;
  return uint32_t(v);
}

}  // namespace

uint32_t max_image_size() {
  const uint32_t o = g_override.load(std::memory_order_relaxed);
  return o ? o : from_environment();
}

void set_max_image_size(uint32_t size) { g_override.store(size, std::memory_order_relaxed); }

void check_image_size(const std::string& path, uint64_t width, uint64_t height) {
  if (width == 0 || height == 0)
    throw file_error(path, "empty image (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  const uint32_t lim = max_image_size();
  if (width > lim || height > lim)
    throw file_error(path, std::to_string(width) + "x" + std::to_string(height) + " is over the size limit of " +
                               std::to_string(lim) + "x" + std::to_string(lim) +
                               " texels per level (AHDPACK_MAX_SIZE raises it)");
}

}  // namespace ahd

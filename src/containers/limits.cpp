#include "containers/limits.h"

#include <atomic>

#include "core/error.h"

namespace ahd {
namespace {

std::atomic<uint32_t> g_override{0};

}  // namespace

uint32_t max_image_size() {
  const uint32_t o = g_override.load(std::memory_order_relaxed);
  return o ? o : kDefaultMaxImageSize;
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

namespace ahd {

void check_layered_size(const std::string& path, uint64_t width, uint64_t height, uint64_t layers) {
  check_image_size(path, width, height);
  const uint64_t lim = max_image_size();
  if (layers == 0 || width * height * layers > lim * lim)
    throw file_error(path, std::to_string(layers) + " layers of " + std::to_string(width) + "x" + std::to_string(height) +
                               " are over the size limit of " + std::to_string(lim) + "x" + std::to_string(lim) +
                               " texels per level, all layers together (AHDPACK_MAX_SIZE raises it)");
}

}  // namespace ahd

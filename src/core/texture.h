// A texture as containers store it: one pixel format, a chain of mip levels, key/value metadata.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/pixel_format.h"

namespace ahd {

struct TextureLevel {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> data;  // level_size_bytes(format, width, height) bytes, rows top first
};

struct Texture {
  PixelFormat format = PixelFormat::RGBA16_SFLOAT;
  std::vector<TextureLevel> levels;  // levels[0] is the full-size image, then each mip
  // Key/value metadata, written in this order (KTX2 sorts keys on write as its spec requires).
  std::vector<std::pair<std::string, std::string>> metadata;
};

// Throws ahd::Error("<what>: …") unless the texture has 1..full_mip_count levels of the chain's
// sizes (max(1, n >> level)), each holding exactly level_size_bytes(), and a size in [1, max_dim].
void check_texture_levels(const Texture& tex, const char* what, uint32_t max_dim);

}  // namespace ahd

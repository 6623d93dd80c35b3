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
  std::vector<uint8_t> data;  // layers × level_size_bytes(format, width, height) bytes, layer by layer, rows top first
};

struct Texture {
  PixelFormat format = PixelFormat::RGBA16_SFLOAT;
  std::vector<TextureLevel> levels;  // levels[0] is the full-size image, then each mip
  // Key/value metadata, written in this order (KTX2 sorts keys on write as its spec requires).
  std::vector<std::pair<std::string, std::string>> metadata;
  uint32_t layers = 1;  // array layers (an atlas of several pages); every level holds all of them
};

// Throws ahd::Error("<what>: …") unless the texture has 1..full_mip_count levels of the chain's
// sizes (max(1, n >> level)), each holding exactly level_size_bytes(), and a size in [1, max_dim].
// Levels hold layers × that size; layers must be ≥ 1.
void check_texture_levels(const Texture& tex, const char* what, uint32_t max_dim);

// Layer `layer` of an array texture as a one-layer texture (same format, levels and metadata).
// Throws ahd::Error when the layer does not exist.
Texture texture_layer(const Texture& tex, uint32_t layer);

// Stacks one-layer textures of the same format, size and level count into one array texture
// (metadata from the first). Throws ahd::Error when they differ.
Texture stack_layers(const std::vector<Texture>& layers);

}  // namespace ahd

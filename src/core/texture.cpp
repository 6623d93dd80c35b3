#include "core/texture.h"

#include <algorithm>

#include "core/error.h"

namespace ahd {

void check_texture_levels(const Texture& tex, const char* what, uint32_t max_dim) {
  if (tex.levels.empty()) throw Error(std::string(what) + ": texture has no levels");
  const uint32_t w = tex.levels[0].width, h = tex.levels[0].height;
  if (w == 0 || h == 0 || w > max_dim || h > max_dim) throw Error(std::string(what) + ": invalid texture size");
  if (tex.layers == 0) throw Error(std::string(what) + ": texture has no layers");
  if (tex.levels.size() > full_mip_count(w, h)) throw Error(std::string(what) + ": more mip levels than the size allows");
  for (size_t l = 0; l < tex.levels.size(); ++l) {
    const TextureLevel& lv = tex.levels[l];
    if (lv.width != std::max(1u, w >> l) || lv.height != std::max(1u, h >> l) ||
        lv.data.size() != size_t(tex.layers) * level_size_bytes(tex.format, lv.width, lv.height))
      throw Error(std::string(what) + ": level " + std::to_string(l) + " has the wrong size or byte count");
  }
}

Texture texture_layer(const Texture& tex, uint32_t layer) {
  if (layer >= tex.layers)
    throw Error("layer " + std::to_string(layer) + " does not exist (the texture has " + std::to_string(tex.layers) + ")");
  Texture t;
  t.format = tex.format;
  t.metadata = tex.metadata;
  for (const TextureLevel& lv : tex.levels) {
    const size_t n = level_size_bytes(tex.format, lv.width, lv.height);
    const auto from = lv.data.begin() + std::ptrdiff_t(n * layer);
    t.levels.push_back({lv.width, lv.height, std::vector<uint8_t>(from, from + std::ptrdiff_t(n))});
  }
  return t;
}

Texture stack_layers(const std::vector<Texture>& layers) {
  if (layers.empty()) throw Error("no layers to stack");
  Texture t;
  t.format = layers[0].format;
  t.metadata = layers[0].metadata;
  t.layers = uint32_t(layers.size());
  t.levels.resize(layers[0].levels.size());
  for (const Texture& l : layers) {
    if (l.format != t.format || l.layers != 1 || l.levels.size() != t.levels.size())
      throw Error("array layers differ in format or level count");
    for (size_t i = 0; i < t.levels.size(); ++i) {
      if (l.levels[i].width != layers[0].levels[i].width || l.levels[i].height != layers[0].levels[i].height)
        throw Error("array layers differ in size");
      t.levels[i].width = l.levels[i].width, t.levels[i].height = l.levels[i].height;
      t.levels[i].data.insert(t.levels[i].data.end(), l.levels[i].data.begin(), l.levels[i].data.end());
    }
  }
  return t;
}

}  // namespace ahd

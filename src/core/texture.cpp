#include "core/texture.h"

#include <algorithm>

#include "core/error.h"

namespace ahd {

void check_texture_levels(const Texture& tex, const char* what, uint32_t max_dim) {
  if (tex.levels.empty()) throw Error(std::string(what) + ": texture has no levels");
  const uint32_t w = tex.levels[0].width, h = tex.levels[0].height;
  if (w == 0 || h == 0 || w > max_dim || h > max_dim) throw Error(std::string(what) + ": invalid texture size");
  if (tex.levels.size() > full_mip_count(w, h)) throw Error(std::string(what) + ": more mip levels than the size allows");
  for (size_t l = 0; l < tex.levels.size(); ++l) {
    const TextureLevel& lv = tex.levels[l];
    if (lv.width != std::max(1u, w >> l) || lv.height != std::max(1u, h >> l) ||
        lv.data.size() != level_size_bytes(tex.format, lv.width, lv.height))
      throw Error(std::string(what) + ": level " + std::to_string(l) + " has the wrong size or byte count");
  }
}

}  // namespace ahd

#include "image/texture_image.h"

#include <cstring>

#include "containers/container.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"
#include "pipeline/plane_codec.h"

namespace ahd {

bool is_texture_container_bytes(const std::vector<uint8_t>& bytes) {
  static const uint8_t ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
  if (bytes.size() >= sizeof ktx2 && std::memcmp(bytes.data(), ktx2, sizeof ktx2) == 0) return true;
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "DDS ", 4) == 0;
}

namespace {

// The texture's level 0 checked as one lightmap, and its header as an image's.
Texture open_texture(const std::string& path, const std::vector<uint8_t>& bytes, int part, ImageFileInfo* info) {
  Texture tex = decode_container_auto(bytes.data(), bytes.size(), path);
  if (part != 0) throw file_error(path, "no part " + std::to_string(part) + " (a texture file has one)");
  if (tex.layers != 1)
    throw file_error(path, "is an array texture of " + std::to_string(tex.layers) +
                               " layers: one lightmap per file is read (ahdpack's own outputs decode with ahdpack decode)");
  if (tex.levels.empty()) throw file_error(path, "holds no level");
  const FormatInfo& fi = pixel_format_row(tex.format).info;
  static const char* const names[4] = {"R", "G", "B", "A"};
  *info = ImageFileInfo{};
  info->width = int(tex.levels[0].width);
  info->height = int(tex.levels[0].height);
  for (int c = 0; c < fi.channels && c < 4; ++c) info->channel_names.push_back(names[c]);
  info->is_float = fi.is_float;
  info->parts = {""};
  return tex;
}

}  // namespace

ImageFileInfo read_texture_info(const std::string& path, const std::vector<uint8_t>& bytes, int part) {
  ImageFileInfo info;
  open_texture(path, bytes, part, &info);
  return info;
}

ImageF read_texture_image(const std::string& path, const std::vector<uint8_t>& bytes, int part, ImageFileInfo* info) {
  ImageFileInfo header;
  const Texture tex = open_texture(path, bytes, part, &header);
  if (info) *info = header;
  try {
    return decode_plane(tex.format, tex.levels[0]);
  } catch (const Error& e) {
    throw file_error(path, std::string(pixel_format_row(tex.format).info.name) + ": " + e.what());
  }
}

}  // namespace ahd

#include "core/pixel_format.h"

#include "codecs/pixel_format_table.h"

namespace ahd {

const FormatInfo& format_info(PixelFormat f) { return pixel_format_row(f).info; }

bool format_from_name(const std::string& name, PixelFormat* out) {
  for (const PixelFormatRow& row : pixel_format_rows())
    if (name == row.info.name) return *out = row.info.format, true;
  return false;
}

// 0 is the rows' "no code" (VK_FORMAT_UNDEFINED, DXGI_FORMAT_UNKNOWN): it names no format.
bool format_from_vk(uint32_t vk, PixelFormat* out) {
  if (vk == 0) return false;
  for (const PixelFormatRow& row : pixel_format_rows())
    if (row.info.vk_format == vk) return *out = row.info.format, true;
  return false;
}

bool format_from_dxgi(uint32_t dxgi, PixelFormat* out) {
  if (dxgi == 0) return false;
  for (const PixelFormatRow& row : pixel_format_rows())
    if (row.info.dxgi_format == dxgi) return *out = row.info.format, true;
  return false;
}

uint32_t full_mip_count(uint32_t width, uint32_t height) {
  uint32_t n = 1;
  for (uint32_t m = width > height ? width : height; m > 1; m >>= 1) ++n;
  return n;
}

size_t level_size_bytes(PixelFormat f, uint32_t width, uint32_t height) {
  const FormatInfo& info = format_info(f);
  const size_t bw = (size_t(width) + info.block_width - 1) / info.block_width;
  const size_t bh = (size_t(height) + info.block_height - 1) / info.block_height;
  return bw * bh * size_t(info.bytes_per_block);
}

}  // namespace ahd

#include "core/pixel_format.h"

#include <iterator>

namespace ahd {
namespace {

// GL enums, spelled out so this file needs no GL header.
constexpr uint32_t GL_R8 = 0x8229, GL_RG8 = 0x822B, GL_RGBA8 = 0x8058, GL_RGBA16F = 0x881A,
                   GL_RGBA32F = 0x8814, GL_R11F_G11F_B10F = 0x8C3A, GL_RGB9_E5 = 0x8C3D,
                   GL_COMPRESSED_RED_RGTC1 = 0x8DBB, GL_COMPRESSED_RG_RGTC2 = 0x8DBD,
                   GL_COMPRESSED_RGB_BPTC_SIGNED_FLOAT = 0x8E8E,
                   GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT = 0x8E8F;

const FormatInfo kFormats[] = {
    {PixelFormat::R8_UNORM, "r8", 9, 61, GL_R8, 1, 1, 1, 1, false, false},
    {PixelFormat::RG8_UNORM, "rg8", 16, 49, GL_RG8, 1, 1, 2, 2, false, false},
    {PixelFormat::RGBA8_UNORM, "rgba8", 37, 28, GL_RGBA8, 1, 1, 4, 4, false, false},
    {PixelFormat::RGBA16_SFLOAT, "rgba16f", 97, 10, GL_RGBA16F, 1, 1, 8, 4, true, false},
    {PixelFormat::RGBA32_SFLOAT, "rgba32f", 109, 2, GL_RGBA32F, 1, 1, 16, 4, true, false},
    {PixelFormat::B10G11R11_UFLOAT, "b10g11r11", 122, 26, GL_R11F_G11F_B10F, 1, 1, 4, 3, true, false},
    {PixelFormat::E5B9G9R9_UFLOAT, "rgb9e5", 123, 67, GL_RGB9_E5, 1, 1, 4, 3, true, false},
    {PixelFormat::BC4_UNORM, "bc4", 139, 80, GL_COMPRESSED_RED_RGTC1, 4, 4, 8, 1, false, true},
    {PixelFormat::BC5_UNORM, "bc5", 141, 83, GL_COMPRESSED_RG_RGTC2, 4, 4, 16, 2, false, true},
    {PixelFormat::BC6H_UFLOAT, "bc6h", 143, 95, GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT, 4, 4, 16, 3, true, true},
    {PixelFormat::BC6H_SFLOAT, "bc6h-signed", 144, 96, GL_COMPRESSED_RGB_BPTC_SIGNED_FLOAT, 4, 4, 16, 3, true, true},
};

}  // namespace

const FormatInfo& format_info(PixelFormat f) { return kFormats[size_t(f)]; }

bool format_from_name(const std::string& name, PixelFormat* out) {
  for (const auto& info : kFormats) {
    if (name == info.name) {
      *out = info.format;
      return true;
    }
  }
  return false;
}

bool format_from_vk(uint32_t vk, PixelFormat* out) {
  for (const auto& info : kFormats)
    if (info.vk_format == vk) return *out = info.format, true;
  return false;
}

bool format_from_dxgi(uint32_t dxgi, PixelFormat* out) {
  for (const auto& info : kFormats)
    if (info.dxgi_format == dxgi) return *out = info.format, true;
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

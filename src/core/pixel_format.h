// The texel formats ahdpack writes, with the facts containers and codecs need about each. Every
// fact about a format is its row in codecs/pixel_format_table.cpp (docs/maintaining.md "Adding a pixel format").
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace ahd {

enum class PixelFormat : uint8_t {
  R8_UNORM,
  RG8_UNORM,
  RGBA8_UNORM,
  RGBA16_SFLOAT,
  RGBA32_SFLOAT,
  B10G11R11_UFLOAT,  // Vulkan B10G11R11_UFLOAT_PACK32 == DXGI R11G11B10_FLOAT (R in the low bits)
  E5B9G9R9_UFLOAT,   // Vulkan E5B9G9R9_UFLOAT_PACK32 == DXGI R9G9B9E5_SHAREDEXP
  BC4_UNORM,
  BC5_UNORM,
  BC6H_UFLOAT,
  BC6H_SFLOAT,
  // Not a format: the number of formats above. A new format goes just above it; the registry's
  // static_assert (codecs/pixel_format_table.cpp) fails until its row is in place.
  COUNT,
};

inline constexpr size_t kPixelFormatCount = size_t(PixelFormat::COUNT);

struct FormatInfo {
  PixelFormat format;
  const char* name;        // our name, as used in profiles and manifests ("bc6h-ufloat", ...)
  uint32_t vk_format;      // VkFormat enum value (KTX2 vkFormat field)
  uint32_t dxgi_format;    // DXGI_FORMAT enum value (DDS DX10 header); 0 (DXGI_FORMAT_UNKNOWN) = none
  uint32_t gl_internal;    // OpenGL internal format (for the GL tests)
  int block_width;         // 1 for uncompressed formats, 4 for BCn
  int block_height;
  int bytes_per_block;     // bytes per texel for uncompressed formats
  int channels;            // meaningful channels (R=1, RG=2, RGB=3, RGBA=4)
  bool is_float;
  bool is_compressed;
};

// The facts of a format (its row's `info`). Throws ahd::Error for a value that is not a format.
const FormatInfo& format_info(PixelFormat f);

// Looks a format up by its name; returns false when no format has that name.
bool format_from_name(const std::string& name, PixelFormat* out);

// Bytes of one mip level of w×h texels (whole blocks for compressed formats).
size_t level_size_bytes(PixelFormat f, uint32_t width, uint32_t height);

// Looks a format up by its VkFormat / DXGI_FORMAT value; false when we do not support it. 0
// (VK_FORMAT_UNDEFINED, DXGI_FORMAT_UNKNOWN) never matches: it is how a row says it has no code.
bool format_from_vk(uint32_t vk_format, PixelFormat* out);
bool format_from_dxgi(uint32_t dxgi_format, PixelFormat* out);

// Levels of the full mip chain of a w×h image: 1 + floor(log2(max(w, h))).
uint32_t full_mip_count(uint32_t width, uint32_t height);

}  // namespace ahd

#include "containers/dds.h"

#include <algorithm>

#include "containers/byte_io.h"
#include "containers/limits.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"

namespace ahd {
namespace {

constexpr uint32_t kMagic = 0x20534444;  // "DDS "
constexpr uint32_t kHeaderSize = 124, kPixelFormatSize = 32;
constexpr uint32_t DDSD_CAPS = 0x1, DDSD_HEIGHT = 0x2, DDSD_WIDTH = 0x4, DDSD_PITCH = 0x8,
                   DDSD_PIXELFORMAT = 0x1000, DDSD_MIPMAPCOUNT = 0x20000, DDSD_LINEARSIZE = 0x80000;
constexpr uint32_t DDPF_ALPHAPIXELS = 0x1, DDPF_FOURCC = 0x4, DDPF_RGB = 0x40;
constexpr uint32_t DDSCAPS_COMPLEX = 0x8, DDSCAPS_TEXTURE = 0x1000, DDSCAPS_MIPMAP = 0x400000;
constexpr uint32_t kResourceTexture2D = 3;
constexpr uint32_t kMaxDimension = 1u << 16;
constexpr uint32_t kMaxLayers = 2048;  // D3D11's array limit

constexpr uint32_t fourcc(char a, char b, char c, char d) {
  return uint32_t(uint8_t(a)) | uint32_t(uint8_t(b)) << 8 | uint32_t(uint8_t(c)) << 16 | uint32_t(uint8_t(d)) << 24;
}

// pitchOrLinearSize per the DDS docs: linear size of level 0 for block formats, else the row pitch.
uint32_t pitch_or_linear_size(PixelFormat f, uint32_t w, uint32_t h) {
  const FormatInfo& fi = format_info(f);
  if (fi.is_compressed) return uint32_t(level_size_bytes(f, w, h));
  return w * uint32_t(fi.bytes_per_block);
}

}  // namespace

std::vector<uint8_t> write_dds(const Texture& tex) {
  using namespace bytes;
  check_texture_levels(tex, "DDS", kMaxDimension);
  const uint32_t w = tex.levels[0].width, h = tex.levels[0].height;
  const PixelFormatRow& row = pixel_format_row(tex.format);
  const FormatInfo& fi = row.info;
  if (!(row.containers & kInDds)) throw Error(std::string("DDS: cannot hold ") + fi.name);
  const uint32_t levels = uint32_t(tex.levels.size());
  std::vector<uint8_t> b;
  put32(b, kMagic);
  put32(b, kHeaderSize);
  put32(b, DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | DDSD_PIXELFORMAT | DDSD_MIPMAPCOUNT |
               (fi.is_compressed ? DDSD_LINEARSIZE : DDSD_PITCH));
  put32(b, h);
  put32(b, w);
  put32(b, pitch_or_linear_size(tex.format, w, h));
  put32(b, 0);       // depth
  put32(b, levels);  // mipMapCount
  for (int i = 0; i < 11; ++i) put32(b, 0);
  // Like DirectXTex, a legacy pixel format where one describes the format exactly (more readers
  // understand it, OpenImageIO among them), the DX10 extension for everything else.
  // Arrays need the DX10 header (its arraySize) whatever the format.
  const DdsFacts& dds = row.dds;
  const bool legacy_fourcc = tex.layers == 1 && dds.fourcc != 0;
  const bool legacy_rgb = tex.layers == 1 && dds.rgb_bits != 0;
  put32(b, kPixelFormatSize);
  if (legacy_rgb) {
    put32(b, DDPF_RGB | (dds.masks[3] ? DDPF_ALPHAPIXELS : 0));
    put32(b, 0);
    put32(b, dds.rgb_bits);
    for (uint32_t m : dds.masks) put32(b, m);
  } else {
    put32(b, DDPF_FOURCC);
    put32(b, legacy_fourcc ? dds.fourcc : fourcc('D', 'X', '1', '0'));
    for (int i = 0; i < 5; ++i) put32(b, 0);  // bit count and masks
  }
  put32(b, DDSCAPS_TEXTURE | (levels > 1 ? DDSCAPS_COMPLEX | DDSCAPS_MIPMAP : 0));
  for (int i = 0; i < 4; ++i) put32(b, 0);  // caps2..4, reserved2
  if (!legacy_fourcc && !legacy_rgb) {      // DDS_HEADER_DXT10
    put32(b, fi.dxgi_format);
    put32(b, kResourceTexture2D);
    put32(b, 0);  // miscFlag
    put32(b, tex.layers);  // arraySize
    put32(b, 0);  // miscFlags2: alpha mode unknown
  }
  // DDS stores each array layer's whole mip chain in turn.
  for (uint32_t layer = 0; layer < tex.layers; ++layer)
    for (const TextureLevel& lv : tex.levels) {
      const size_t n = lv.data.size() / tex.layers;
      b.insert(b.end(), lv.data.begin() + std::ptrdiff_t(n * layer), lv.data.begin() + std::ptrdiff_t(n * (layer + 1)));
    }
  return b;
}

Texture read_dds(const uint8_t* data, size_t size, const std::string& path) {
  bytes::Reader r(data, size, path);
  if (size < 4 + kHeaderSize || r.u32(0) != kMagic) r.fail("not a DDS file (bad magic)");
  if (r.u32(4) != kHeaderSize || r.u32(76) != kPixelFormatSize) r.fail("invalid DDS header size");
  const uint32_t h = r.u32(12), w = r.u32(16), depth = r.u32(24);
  uint32_t levels = r.u32(28);
  const uint32_t pf_flags = r.u32(80), cc = r.u32(84);
  if (w == 0 || h == 0 || w > kMaxDimension || h > kMaxDimension)
    r.fail("unsupported size " + std::to_string(w) + "x" + std::to_string(h));
  check_image_size(path, w, h);
  if (depth > 1) r.fail("volume textures are not supported");
  if (levels == 0) levels = 1;
  if (levels > full_mip_count(w, h)) r.fail("invalid mip count " + std::to_string(levels));
  Texture tex;
  size_t data_at = 4 + kHeaderSize;
  // A legacy encoding some row writes or reads (codecs/pixel_format_table.h DdsFacts).
  auto legacy = [&](auto matches) {
    for (const PixelFormatRow& row : pixel_format_rows())
      if (matches(row.dds)) return tex.format = row.info.format, true;
    return false;
  };
  auto rgb_matches = [&](const DdsFacts& d) {
    return d.rgb_bits != 0 && r.u32(88) == d.rgb_bits && r.u32(92) == d.masks[0] && r.u32(96) == d.masks[1] &&
           r.u32(100) == d.masks[2] && r.u32(104) == d.masks[3] && (d.masks[3] == 0 || (pf_flags & DDPF_ALPHAPIXELS));
  };
  const bool rgb_masks = (pf_flags & DDPF_RGB) && legacy(rgb_matches);
  if (rgb_masks) {
    // legacy() has set the format
  } else if (!(pf_flags & DDPF_FOURCC)) {
    r.fail("unsupported DDS pixel format (we read DX10, BC4U/ATI1, BC5U/ATI2 and 32-bit RGBA)");
  } else if (cc == fourcc('D', 'X', '1', '0')) {
    const uint32_t dxgi = r.u32(128), dim = r.u32(132), misc = r.u32(136), array = r.u32(140);
    if (!format_from_dxgi(dxgi, &tex.format) || !(pixel_format_row(tex.format).containers & kInDds))
      r.fail("unsupported DXGI format " + std::to_string(dxgi));
    if (dim != kResourceTexture2D) r.fail("only 2D textures are supported");
    if (misc & 0x4) r.fail("cube maps are not supported");
    if (array == 0 || array > kMaxLayers) r.fail("unsupported array size " + std::to_string(array));
    check_layered_size(path, w, h, array);
    tex.layers = array;
    data_at += 20;
  } else if (!legacy([&](const DdsFacts& d) { return d.fourcc != 0 && (cc == d.fourcc || cc == d.fourcc_alt); })) {
    r.fail("unsupported FourCC");
  }
  uint64_t total = 0;
  for (uint32_t l = 0; l < levels; ++l) total += level_size_bytes(tex.format, std::max(1u, w >> l), std::max(1u, h >> l));
  r.need(data_at, total * tex.layers, "level data");
  tex.levels.resize(levels);
  size_t at = data_at;
  for (uint32_t layer = 0; layer < tex.layers; ++layer)  // layer by layer, each its mip chain
    for (uint32_t l = 0; l < levels; ++l) {
      TextureLevel& lv = tex.levels[l];
      lv.width = std::max(1u, w >> l);
      lv.height = std::max(1u, h >> l);
      const size_t n = level_size_bytes(tex.format, lv.width, lv.height);
      const uint8_t* src = r.at(at, n, "level data");
      lv.data.insert(lv.data.end(), src, src + n);
      at += n;
    }
  return tex;
}

}  // namespace ahd

#include "pipeline/plane_codec.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "codecs/bc4.h"
#include "codecs/bc5.h"
#include "codecs/bc6h/bc6h_codec.h"
#include "codecs/packed_float.h"
#include "core/error.h"
#include "core/large_buffer.h"

namespace ahd {
namespace {

constexpr float kHalfMax = 65504.0f;

uint8_t to_unorm8(float v) { return uint8_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f)); }

float get(const ImageF& img, size_t i, int c) {
  if (c < img.channels) return img.data[i * img.channels + c];
  return c == 3 ? 1.0f : 0.0f;
}

}  // namespace

bool plane_format_supported(PixelFormat f) {
  switch (f) {
    case PixelFormat::R8_UNORM:
    case PixelFormat::RG8_UNORM:
    case PixelFormat::RGBA8_UNORM:
    case PixelFormat::RGBA16_SFLOAT:
    case PixelFormat::RGBA32_SFLOAT:
    case PixelFormat::B10G11R11_UFLOAT:
    case PixelFormat::E5B9G9R9_UFLOAT:
    case PixelFormat::BC4_UNORM:
    case PixelFormat::BC5_UNORM:
    case PixelFormat::BC6H_UFLOAT:
    case PixelFormat::BC6H_SFLOAT:
      return true;
    default:
      return false;
  }
}

TextureLevel encode_plane(PixelFormat f, const ImageF& img, const PlaneCodecOptions& opt,
                          PlaneCodecStats* stats) {
  TextureLevel lvl;
  lvl.width = uint32_t(img.width);
  lvl.height = uint32_t(img.height);
  assign_large(lvl.data, level_size_bytes(f, lvl.width, lvl.height), uint8_t(0));
  const size_t n = img.texels();
  PlaneCodecStats local;
  PlaneCodecStats& st = stats ? *stats : local;
  switch (f) {
    case PixelFormat::R8_UNORM:
    case PixelFormat::RG8_UNORM:
    case PixelFormat::RGBA8_UNORM: {
      const int ch = format_info(f).channels;
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < ch; ++c) lvl.data[i * ch + c] = to_unorm8(get(img, i, c));
      return lvl;
    }
    case PixelFormat::RGBA16_SFLOAT: {
      uint16_t* out = reinterpret_cast<uint16_t*>(lvl.data.data());
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c) {
          float v = get(img, i, c);
          if (!std::isfinite(v)) {
            st.non_finite++;
            v = std::isnan(v) ? 0.0f : (v > 0 ? kHalfMax : -kHalfMax);
          } else if (std::fabs(v) > kHalfMax) {
            st.clamped++;
            v = std::copysign(kHalfMax, v);
          }
          out[i * 4 + c] = Imath::half(v).bits();
        }
      return lvl;
    }
    case PixelFormat::RGBA32_SFLOAT: {
      float* out = reinterpret_cast<float*>(lvl.data.data());
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c) out[i * 4 + c] = get(img, i, c);
      return lvl;
    }
    case PixelFormat::B10G11R11_UFLOAT:
    case PixelFormat::E5B9G9R9_UFLOAT: {
      PackStats ps;
      const bool e5 = f == PixelFormat::E5B9G9R9_UFLOAT;
      for (size_t i = 0; i < n; ++i) {
        const float r = get(img, i, 0), g = get(img, i, 1), b = get(img, i, 2);
        const uint32_t v = e5 ? pack_rgb9e5(r, g, b, &ps) : pack_b10g11r11(r, g, b, &ps);
        std::memcpy(&lvl.data[i * 4], &v, 4);
      }
      st.clamped += ps.negative + ps.too_large;
      st.non_finite += ps.non_finite;
      return lvl;
    }
    case PixelFormat::BC4_UNORM:
      lvl.data = bc4_encode_image(img, 0, opt.threads);
      return lvl;
    case PixelFormat::BC5_UNORM:
      lvl.data = bc5_encode_image(img, opt.threads);
      return lvl;
    case PixelFormat::BC6H_UFLOAT:
    case PixelFormat::BC6H_SFLOAT: {
      Bc6hOptions o;
      o.is_signed = f == PixelFormat::BC6H_SFLOAT;
      o.quality = opt.bc6h_quality;
      o.threads = opt.threads;
      Bc6hStats bs;
      lvl.data = bc6h_encode_image(img, o, &bs);
      st.clamped += bs.too_large + bs.negative;
      st.non_finite += bs.nan + bs.inf;
      return lvl;
    }
    default:
      break;
  }
  throw Error(std::string("format ") + format_info(f).name + " is not available in this build");
}

ImageF decode_plane(PixelFormat f, const TextureLevel& lvl) {
  if (lvl.data.size() != level_size_bytes(f, lvl.width, lvl.height))
    throw Error(std::string("level data size does not match its dimensions for ") + format_info(f).name);
  const int ch = format_info(f).channels;
  ImageF img(int(lvl.width), int(lvl.height), ch);
  const size_t n = img.texels();
  switch (f) {
    case PixelFormat::R8_UNORM:
    case PixelFormat::RG8_UNORM:
    case PixelFormat::RGBA8_UNORM:
      for (size_t i = 0; i < n * ch; ++i) img.data[i] = lvl.data[i] / 255.0f;
      return img;
    case PixelFormat::RGBA16_SFLOAT: {
      const uint16_t* in = reinterpret_cast<const uint16_t*>(lvl.data.data());
      for (size_t i = 0; i < n * 4; ++i) {
        Imath::half h;
        h.setBits(in[i]);
        img.data[i] = float(h);
      }
      return img;
    }
    case PixelFormat::RGBA32_SFLOAT:
      std::memcpy(img.data.data(), lvl.data.data(), n * 16);
      return img;
    case PixelFormat::B10G11R11_UFLOAT:
    case PixelFormat::E5B9G9R9_UFLOAT:
      for (size_t i = 0; i < n; ++i) {
        uint32_t v;
        std::memcpy(&v, &lvl.data[i * 4], 4);
        if (f == PixelFormat::E5B9G9R9_UFLOAT) unpack_rgb9e5(v, &img.data[i * 3]);
        else unpack_b10g11r11(v, &img.data[i * 3]);
      }
      return img;
    case PixelFormat::BC4_UNORM:
      bc4_decode_image(lvl.data.data(), img.width, img.height, 8, 0, img, 0);
      return img;
    case PixelFormat::BC5_UNORM:
      return bc5_decode_image(lvl.data.data(), img.width, img.height);
    case PixelFormat::BC6H_UFLOAT:
    case PixelFormat::BC6H_SFLOAT:
      return bc6h_decode_image(lvl.data.data(), img.width, img.height, f == PixelFormat::BC6H_SFLOAT);
    default:
      break;
  }
  throw Error(std::string("format ") + format_info(f).name + " is not available in this build");
}

void decode_plane_texel(PixelFormat f, const TextureLevel& lvl, uint32_t x, uint32_t y, float* out) {
  if (lvl.data.size() != level_size_bytes(f, lvl.width, lvl.height))
    throw Error(std::string("level data size does not match its dimensions for ") + format_info(f).name);
  if (x >= lvl.width || y >= lvl.height) throw Error("texel outside the level");
  const FormatInfo& fi = format_info(f);
  const uint32_t bw = uint32_t(fi.block_width), bh = uint32_t(fi.block_height);
  const uint32_t blocks_per_row = (lvl.width + bw - 1) / bw;
  const size_t offset = (size_t(y / bh) * blocks_per_row + x / bw) * size_t(fi.bytes_per_block);
  // Block formats: the texel's block alone, decoded on the stack by the decoder decode_plane uses
  // (the error estimate calls this for each sampled texel of every level: no allocations here).
  const uint8_t* blk = lvl.data.data() + offset;
  const int t = int((y % bh) * bw + (x % bw));
  switch (f) {
    case PixelFormat::BC6H_UFLOAT:
    case PixelFormat::BC6H_SFLOAT: {
      uint16_t h[3];
      bc6h_decode_texel(blk, f == PixelFormat::BC6H_SFLOAT, t, h);
      for (int c = 0; c < 3; ++c) {
        Imath::half v;
        v.setBits(h[c]);
        out[c] = float(v);
      }
      return;
    }
    case PixelFormat::BC4_UNORM:
    case PixelFormat::BC5_UNORM: {
      float v[16];
      for (int c = 0; c < fi.channels; ++c) {
        bc4_decode_block(blk + 8 * c, v);
        out[c] = v[t];
      }
      return;
    }
    default:
      break;
  }
  TextureLevel block;  // the texel's block as a level of its own
  block.width = bw;
  block.height = bh;
  block.data.assign(blk, blk + fi.bytes_per_block);
  const ImageF img = decode_plane(f, block);
  const float* v = img.at(int(x % bw), int(y % bh));
  for (int c = 0; c < fi.channels; ++c) out[c] = v[c];
}

}  // namespace ahd

// The registry of pixel formats: one row per PixelFormat, in enum order, holding everything the
// rest of the code needs to know about the format — its facts (core/pixel_format.h FormatInfo),
// its KTX2 descriptor, its DDS encoding, its GL upload, the containers that hold it and its codec
// (encode, decode, one-texel decode). Containers, plane codecs, decoders and tests iterate or index
// this table; nothing outside codecs/pixel_format_table.cpp switches over PixelFormat.
// docs/maintaining.md "Adding a pixel format" lists what a new format touches.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/image.h"
#include "core/pixel_format.h"
#include "core/texture.h"

namespace ahd {

// What an encoder is given: the thread count and one effort level for every codec. The effort
// uses the BC6H quality scale (0 fast, 1 default, 2 high, 3 max: Bc6hQuality's values); a codec
// without levels ignores it.
struct CodecParams {
  int threads = 0;  // 0 = all hardware threads
  int effort = 1;
};

// What encoding had to clamp (counted, reported).
struct CodecStats {
  size_t clamped = 0;     // values outside the format's range (e.g. > 65504 for half)
  size_t non_finite = 0;  // NaN/Inf inputs
};

// Encodes `img` into `level`, which arrives sized (width, height) and holding level_size_bytes()
// zero bytes; the encoder fills it (or replaces data with a vector of that size). Adds to `stats`.
using EncodeFn = void (*)(const ImageF& img, const CodecParams& params, TextureLevel& level, CodecStats& stats);
// Decodes `level` (its byte size already checked) into `img`, which arrives as a width×height
// image of format_info(f).channels channels; the decoder fills it (or replaces it by one of that shape).
using DecodeFn = void (*)(const TextureLevel& level, ImageF& img);
// Decodes texel t (row-major in its block) of the block at `block` into out[0 .. channels), the
// value the whole-level decode gives. Safe on any block bytes.
using DecodeTexelFn = void (*)(const uint8_t* block, int t, float* out);

// One sample of a KTX2 basic Data Format Descriptor (Khronos Data Format Spec 1.3, section 5.6).
struct Ktx2Sample {
  uint32_t bit_offset, bit_length, channel, lower, upper;
};

inline constexpr int kMaxKtx2Samples = 6;

struct Ktx2Facts {
  uint32_t type_size;    // KTX2 typeSize: 1 for 8-bit and block formats, else the component or packed word size
  uint32_t color_model;  // DFD colorModel (1 RGBSDA, 131 BC4, 132 BC5, 133 BC6H, ...)
  int sample_count;
  Ktx2Sample samples[kMaxKtx2Samples];
};

// How a DDS file names the format besides the DX10 header's DXGI code (FormatInfo::dxgi_format).
// A single-layer texture is written with the legacy encoding when the row has one (as DirectXTex
// does: more readers understand it); arrays always take the DX10 header.
struct DdsFacts {
  uint32_t fourcc = 0;      // legacy FourCC written (0 = none)
  uint32_t fourcc_alt = 0;  // another legacy FourCC read as this format (0 = none)
  uint32_t rgb_bits = 0;    // legacy uncompressed pixel format written: bits per pixel (0 = none)
  uint32_t masks[4] = {};   // with rgb_bits: R, G, B, A masks (A 0 = no alpha)
};

// Which containers hold the format.
enum ContainerBits : uint8_t { kInKtx2 = 1, kInDds = 2 };

struct PixelFormatRow {
  FormatInfo info;
  Ktx2Facts ktx2;
  DdsFacts dds;
  uint32_t gl_format;          // glTexImage2D format and type of an uncompressed format (0 for block formats,
  uint32_t gl_type;            // which upload info.gl_internal with glCompressedTexImage2D)
  uint8_t containers;          // ContainerBits
  EncodeFn encode;             // null: this build cannot encode the format
  DecodeFn decode;             // null: this build cannot decode it
  DecodeTexelFn decode_texel;  // null: one texel is decoded by decoding its block as a level of its own
};

// The row of `f`. Throws ahd::Error for a value that is not a format.
const PixelFormatRow& pixel_format_row(PixelFormat f);

// Every row, in enum order: rows[i].info.format == PixelFormat(i), kPixelFormatCount of them.
std::span<const PixelFormatRow> pixel_format_rows();

}  // namespace ahd

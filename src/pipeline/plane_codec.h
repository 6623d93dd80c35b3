// One image plane ↔ one texture level of a pixel format, through the format's row of the
// registry (codecs/pixel_format_table.h): the checks around every codec, no format named here.
#pragma once
#include <ahd/types.h>
#include <cstddef>

#include "core/image.h"
#include "codecs/pixel_format_table.h"
#include "core/texture.h"

namespace ahd {

struct PlaneCodecOptions {
  int threads = 0;
  // The encoder effort of every codec (CodecParams::effort, on this scale); named after the public
  // option it carries (ConvertOptions::bc6h_quality).
  Bc6hQuality bc6h_quality = Bc6hQuality::Default;
};

// What encoding had to clamp (counted, reported).
using PlaneCodecStats = CodecStats;

// Encodes `img` (floats; UNORM formats take [0,1], float formats take HDR values) into one level.
// Uses the first `format_info(f).channels` channels of img (missing ones read as 0, alpha as 1).
// Throws ahd::Error when the format has no encoder in this build.
TextureLevel encode_plane(PixelFormat f, const ImageF& img, const PlaneCodecOptions& opt,
                          PlaneCodecStats* stats = nullptr);

// Decodes one level to floats, format_info(f).channels channels. Throws ahd::Error when the level's
// byte size does not match its dimensions or the codec is not available.
ImageF decode_plane(PixelFormat f, const TextureLevel& level);

// Decodes the one texel (x, y) of a level into out[0 .. format_info(f).channels): only its block is
// decoded (blocks decode on their own, so the value is the whole-level decode's). Throws
// ahd::Error when (x, y) is outside the level or the level's byte size does not match its size.
void decode_plane_texel(PixelFormat f, const TextureLevel& level, uint32_t x, uint32_t y, float* out);

// True when this build can encode/decode the format.
bool plane_format_supported(PixelFormat f);

}  // namespace ahd

#include "pipeline/plane_codec.h"

#include "core/error.h"
#include "core/large_buffer.h"

namespace ahd {
namespace {

[[noreturn]] void not_available(PixelFormat f) {
  throw Error(std::string("format ") + format_info(f).name + " is not available in this build");
}

void check_level_size(PixelFormat f, const TextureLevel& lvl) {
  if (lvl.data.size() != level_size_bytes(f, lvl.width, lvl.height))
    throw Error(std::string("level data size does not match its dimensions for ") + format_info(f).name);
}

}  // namespace

bool plane_format_supported(PixelFormat f) {
  const PixelFormatRow& row = pixel_format_row(f);
  return row.encode && row.decode;
}

TextureLevel encode_plane(PixelFormat f, const ImageF& img, const PlaneCodecOptions& opt,
                          PlaneCodecStats* stats) {
  const PixelFormatRow& row = pixel_format_row(f);
  if (!row.encode) not_available(f);
  TextureLevel lvl;
  lvl.width = uint32_t(img.width);
  lvl.height = uint32_t(img.height);
  assign_large(lvl.data, level_size_bytes(f, lvl.width, lvl.height), uint8_t(0));
  PlaneCodecStats local;
  CodecParams params;
  params.threads = opt.threads;
  params.effort = int(opt.bc6h_quality);
  row.encode(img, params, lvl, stats ? *stats : local);
  return lvl;
}

ImageF decode_plane(PixelFormat f, const TextureLevel& lvl) {
  check_level_size(f, lvl);
  const PixelFormatRow& row = pixel_format_row(f);
  if (!row.decode) not_available(f);
  ImageF img(int(lvl.width), int(lvl.height), row.info.channels);
  row.decode(lvl, img);
  return img;
}

void decode_plane_texel(PixelFormat f, const TextureLevel& lvl, uint32_t x, uint32_t y, float* out) {
  check_level_size(f, lvl);
  if (x >= lvl.width || y >= lvl.height) throw Error("texel outside the level");
  const PixelFormatRow& row = pixel_format_row(f);
  const FormatInfo& fi = row.info;
  const uint32_t bw = uint32_t(fi.block_width), bh = uint32_t(fi.block_height);
  const uint32_t blocks_per_row = (lvl.width + bw - 1) / bw;
  const size_t offset = (size_t(y / bh) * blocks_per_row + x / bw) * size_t(fi.bytes_per_block);
  // The texel's block alone, decoded on the stack by the row's texel decoder when it has one (the
  // error estimate calls this for each sampled texel of every level: no allocations there).
  const uint8_t* blk = lvl.data.data() + offset;
  if (row.decode_texel) return row.decode_texel(blk, int((y % bh) * bw + (x % bw)), out);
  TextureLevel block;  // the texel's block as a level of its own
  block.width = bw;
  block.height = bh;
  block.data.assign(blk, blk + fi.bytes_per_block);
  const ImageF img = decode_plane(f, block);
  const float* v = img.at(int(x % bw), int(y % bh));
  for (int c = 0; c < fi.channels; ++c) out[c] = v[c];
}

}  // namespace ahd

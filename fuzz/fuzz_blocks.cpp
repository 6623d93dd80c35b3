// The block and packed decoders (BC6H UF16/SF16, BC4, BC5, RGB9E5, B10G11R11...) through
// decode_plane: byte 0 picks the format, bytes 1-2 the level size, the rest is the level's data
// (sizes that do not match are an ahd::Error). Seeds: level data of the golden planes.
#include "core/texture.h"
#include "fuzz_common.h"
#include "pipeline/plane_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const auto f = ahd::PixelFormat(data[0] % ahd::kPixelFormatCount);
  ahd::TextureLevel lv;
  lv.width = 1u + (data[1] & 63);
  lv.height = 1u + (data[2] & 63);
  // Fill exactly one level from the input (repeated), so most inputs reach the decoders.
  const size_t need = ahd::level_size_bytes(f, lv.width, lv.height);
  if (data[1] & 0x80) {
    lv.data.assign(data + 3, data + size);  // raw: a size mismatch must be refused cleanly
  } else {
    lv.data.resize(need);
    for (size_t i = 0; i < need; ++i) lv.data[i] = size > 3 ? data[3 + i % (size - 3)] : 0;
  }
  ahd_fuzz::expect_clean([&] {
    const ahd::ImageF img = ahd::decode_plane(f, lv);
    if (img.texels() != size_t(lv.width) * lv.height) __builtin_trap();
  });
  return 0;
}

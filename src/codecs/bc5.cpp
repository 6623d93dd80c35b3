#include "codecs/bc5.h"

#include <algorithm>

#include "codecs/bc4.h"
#include "core/parallel.h"

namespace ahd {

void bc5_decode_block(const uint8_t block[16], float out[32]) {
  float r[16], g[16];
  bc4_decode_block(block, r);
  bc4_decode_block(block + 8, g);
  for (int i = 0; i < 16; ++i) out[i * 2] = r[i], out[i * 2 + 1] = g[i];
}

std::vector<uint8_t> bc5_encode_image(const ImageF& img, int threads, int effort) {
  const int bw = (img.width + 3) / 4, bh = (img.height + 3) / 4;
  std::vector<uint8_t> out(size_t(bw) * bh * 16);
  parallel_for(size_t(bw) * bh, threads, 64, [&](size_t b) {
    const int bx = int(b % bw), by = int(b / bw);
    for (int c = 0; c < 2; ++c) {
      float v[16];
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
          const int sx = std::min(bx * 4 + x, img.width - 1), sy = std::min(by * 4 + y, img.height - 1);
          v[y * 4 + x] = img.at(sx, sy)[c];
        }
      bc4_encode_block(v, &out[b * 16 + size_t(c) * 8], effort);
    }
  });
  return out;
}

ImageF bc5_decode_image(const uint8_t* blocks, int width, int height) {
  ImageF out(width, height, 2);
  bc4_decode_image(blocks, width, height, 16, 0, out, 0);
  bc4_decode_image(blocks, width, height, 16, 8, out, 1);
  return out;
}

}  // namespace ahd

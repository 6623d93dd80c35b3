// What the BC4/BC5 tests share (tests/unit and tests/accuracy bc4_bc5_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include "codecs/bc4.h"
#include "core/cpu.h"
#include "codecs/bc5.h"

namespace ahd_fixture::bc4_fixture {

using namespace ::ahd;

inline float block_sse(const float v[16], const uint8_t blk[8]) {
  float d[16], e = 0;
  bc4_decode_block(blk, d);
  for (int i = 0; i < 16; ++i) e += (d[i] - v[i]) * (d[i] - v[i]);
  return e;
}

// Best achievable SSE over all 65536 endpoint pairs (each texel takes its nearest palette entry).
inline float exhaustive_sse(const float v[16]) {
  float best = INFINITY, pal[8];
  for (int r0 = 0; r0 < 256; ++r0)
    for (int r1 = 0; r1 < 256; ++r1) {
      bc4_palette(uint8_t(r0), uint8_t(r1), pal);
      float e = 0;
      for (int i = 0; i < 16 && e < best; ++i) {
        float bd = INFINITY;
        for (float p : pal) bd = std::min(bd, (v[i] - p) * (v[i] - p));
        e += bd;
      }
      best = std::min(best, e);
    }
  return best;
}

}  // namespace ahd_fixture::bc4_fixture

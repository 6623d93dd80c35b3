// BC4's encoder against an exhaustive search over many blocks. Unit tests: tests/unit/bc4_bc5_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codecs/bc4.h"
#include "core/cpu.h"
#include "codecs/bc5.h"
#include "bc4_fixture.h"

using namespace ahd;
using namespace ahd_fixture::bc4_fixture;


TEST(Bc4, EncoderIsCloseToExhaustiveSearch) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  double ours = 0, best = 0;
  int blocks = 0;
  for (int b = 0; b < 60; ++b) {
    float v[16];
    const float a = u(rng), s = u(rng) * (b % 3 == 0 ? 1.0f : 0.2f);
    for (int i = 0; i < 16; ++i) {
      v[i] = std::clamp(a + s * (b % 2 ? u(rng) - 0.5f : (i % 4) / 3.0f - 0.5f), 0.0f, 1.0f);
      if (b % 7 == 0 && i < 2) v[i] = float(i);  // blocks touching 0 and 1
    }
    uint8_t blk[8];
    bc4_encode_block(v, blk);
    ours += block_sse(v, blk);
    best += exhaustive_sse(v);
    ++blocks;
  }
  std::printf("BC4 encoder: mean SSE %.3g vs exhaustive optimum %.3g over %d blocks (ratio %.3f)\n", ours / blocks,
              best / blocks, blocks, ours / best);
  EXPECT_LE(ours, best * 1.10 + 1e-9);  // measured 1.04
}

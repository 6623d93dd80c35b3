// BC4/BC5: the palette rules of both modes, exact constant blocks, partial blocks, SIMD = scalar.
// The encoder against an exhaustive search: tests/accuracy/bc4_bc5_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codecs/bc4.h"
#include "core/cpu.h"
#include "codecs/bc5.h"
#include "bc4_fixture.h"

using namespace ahd;
using namespace ahd_fixture::bc4_fixture;

TEST(Bc4, PaletteFollowsBothModes) {
  float pal[8];
  bc4_palette(200, 60, pal);  // r0 > r1: 8 values
  EXPECT_FLOAT_EQ(pal[0], 200 / 255.0f);
  EXPECT_FLOAT_EQ(pal[1], 60 / 255.0f);
  EXPECT_FLOAT_EQ(pal[2], (6 * 200 + 1 * 60) / (7 * 255.0f));
  EXPECT_FLOAT_EQ(pal[7], (1 * 200 + 6 * 60) / (7 * 255.0f));
  bc4_palette(60, 200, pal);  // r0 <= r1: 6 values + 0 and 1
  EXPECT_FLOAT_EQ(pal[2], (4 * 60 + 1 * 200) / (5 * 255.0f));
  EXPECT_FLOAT_EQ(pal[5], (1 * 60 + 4 * 200) / (5 * 255.0f));
  EXPECT_EQ(pal[6], 0.0f);
  EXPECT_EQ(pal[7], 1.0f);
  // Index bits: texel i at bits 3i of bytes 2..7, little endian.
  const uint8_t blk[8] = {255, 0, 0b11111010, 0, 0, 0, 0, 0b11100000};  // t0 = 2, t1 = 7, t2 = 3, t15 = 7
  float out[16];
  bc4_decode_block(blk, out);
  EXPECT_FLOAT_EQ(out[0], (6 * 255) / (7 * 255.0f));
  EXPECT_FLOAT_EQ(out[1], 255 / (7 * 255.0f));
  EXPECT_FLOAT_EQ(out[15], 255 / (7 * 255.0f));
  EXPECT_FLOAT_EQ(out[2], (5 * 255) / (7 * 255.0f));
}

TEST(Bc4, ConstantBlocksAreExact) {
  for (int q = 0; q < 256; ++q) {
    float v[16];
    std::fill(v, v + 16, q / 255.0f);
    uint8_t blk[8];
    bc4_encode_block(v, blk);
    EXPECT_EQ(block_sse(v, blk), 0.0f) << q;
  }
}

TEST(Bc5, RoundTripAndPartialBlocks) {
  ImageF img(7, 5, 2);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) {
      img.at(x, y)[0] = x / 6.0f;
      img.at(x, y)[1] = y / 4.0f;
    }
  for (int threads : {1, 2}) {
    const std::vector<uint8_t> b = bc5_encode_image(img, threads);
    ASSERT_EQ(b.size(), size_t(2 * 2 * 16));
    const ImageF d = bc5_decode_image(b.data(), 7, 5);
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 7; ++x)
        for (int c = 0; c < 2; ++c) EXPECT_NEAR(d.at(x, y)[c], img.at(x, y)[c], 1.0f / 255) << x << "," << y;
    if (threads == 2) EXPECT_EQ(b, bc5_encode_image(img, 1));
  }
}

TEST(Bc4, SimdAndScalarIndexStepsWriteTheSameBytes) {
  // The search evaluates its endpoint pairs 16, 8 or 4 to a register (AVX-512, AVX2, SSE2) and the
  // winner's index step runs the 16 texels in one AVX-512 register, two AVX2 ones or four SSE2
  // ones (whichever the CPU has); forced below each, the next narrower path, down to the plain loops.
  // Random blocks of many kinds (ramps, clusters, ties between palette entries, ends of the
  // range), every effort, BC4 and BC5: the same bytes.
  std::mt19937 rng(28);
  std::uniform_real_distribution<float> u(0, 1);
  ImageF img(64, 64, 2);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 2; ++c) {
        const int kind = (x / 4 + y / 4 * 16 + c) % 5;
        float v = u(rng);
        if (kind == 1) v = 0.2f + 0.01f * float(x % 4 + 4 * (y % 4));           // ramp
        if (kind == 2) v = (x + y) % 2 ? 0.3f : 0.7f;                           // two clusters
        if (kind == 3) v = float(int(u(rng) * 8)) / 7.0f;                       // on palette entries
        if (kind == 4) v = u(rng) < 0.5f ? 0.0f : 1.0f - 0.001f * float(x % 4);  // ends of the range
        img.at(x, y)[c] = v;
      }
  // More kinds in the lower half: tiny ranges, NaN / ±inf / out of range, neighbouring 8-bit steps.
  for (int y = 32; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 2; ++c) {
        const int kind = (x / 4 + y / 4 * 16 + c) % 3;
        float& v = img.at(x, y)[c];
        if (kind == 0) v = 0.4f + 1e-3f * u(rng);
        if (kind == 1 && (x + 2 * y) % 5 == 0) v = (x % 3 == 0) ? NAN : (x % 3 == 1) ? INFINITY : -2.0f;
        if (kind == 2) v = float(100 + (x * 7 + y * 3) % 5) / 255.0f;
      }
  // Each path in turn: the plain loops, SSE2, AVX2 (4-pair batches on SSE2), AVX-512 without AVX2
  // (its small batches on SSE2), everything the CPU has.
  for (int effort = 0; effort < 3; ++effort) {
    cpu::disable_for_tests(cpu::kAllSimd);
    const std::vector<uint8_t> s4 = bc4_encode_image(img, 1, 1, effort), s5 = bc5_encode_image(img, 1, effort);
    for (unsigned mask : {cpu::kAboveSse2, cpu::kAboveAvx2, unsigned(cpu::kAvx2), 0u}) {
      cpu::disable_for_tests(mask);
      EXPECT_EQ(s4, bc4_encode_image(img, 1, 1, effort)) << effort << " mask " << mask;
      EXPECT_EQ(s5, bc5_encode_image(img, 1, effort)) << effort << " mask " << mask;
    }
    cpu::disable_for_tests(0);
  }
}

TEST(Bc4, BatchedSearchWritesTheBytesOfTheOneByOneSearch) {
  // The encoder evaluates its candidate endpoint pairs in batches (SIMD lanes, groups that stop
  // early once no lane can win, the winner's indices computed once); the reference in
  // bc4_fixture.h tries them one at a time as the search did before. Same bytes for every block
  // kind (ties between pairs included: the first of equal errors must win), effort and path.
  std::mt19937 rng(4);
  std::vector<float> blocks;
  for (int b = 0; b < 2400; ++b) {
    float v[16];
    make_bc4_test_block(rng, b % 12, v);
    blocks.insert(blocks.end(), v, v + 16);
  }
  for (int effort = 0; effort < 3; ++effort) {
    std::vector<uint8_t> want(blocks.size() / 2);
    for (size_t b = 0; b < blocks.size() / 16; ++b) reference_bc4_encode_block(&blocks[b * 16], &want[b * 8], effort);
    for (unsigned mask : {cpu::kAllSimd, cpu::kAboveSse2, cpu::kAboveAvx2, unsigned(cpu::kAvx2), 0u}) {
      cpu::disable_for_tests(mask);
      int differ = 0;
      for (size_t b = 0; b < blocks.size() / 16; ++b) {
        uint8_t got[8];
        bc4_encode_block(&blocks[b * 16], got, effort);
        if (!std::equal(got, got + 8, &want[b * 8]) && ++differ <= 3)
          ADD_FAILURE() << "block " << b << " (kind " << b % 12 << "), effort " << effort << ", mask " << mask;
      }
      EXPECT_EQ(differ, 0) << "effort " << effort << ", mask " << mask;
    }
    cpu::disable_for_tests(0);
  }
}

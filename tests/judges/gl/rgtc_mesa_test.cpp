// BC4/BC5 decoders against Mesa's software GL (GL_COMPRESSED_RED_RGTC1 / RG_RGTC2), bit for bit,
// on random blocks of both endpoint orders and on the blocks our encoder writes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codecs/bc4.h"
#include "codecs/bc5.h"
#include "gl_fixture.h"

using namespace ahd;

namespace {

// Decodes `blocks` (W×H texels) with Mesa to 8-bit texels of `channels` channels.
std::vector<uint8_t> mesa_decode(GLenum internal, const std::vector<uint8_t>& blocks, int W, int H, int channels) {
  GLuint tex;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glCompressedTexImage2D(GL_TEXTURE_2D, 0, internal, W, H, 0, GLsizei(blocks.size()), blocks.data());
  std::vector<uint8_t> out(size_t(W) * H * channels);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTexImage(GL_TEXTURE_2D, 0, channels == 1 ? GL_RED : GL_RG, GL_UNSIGNED_BYTE, out.data());
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  glDeleteTextures(1, &tex);
  return out;
}

// Our 8-bit decode of the same layout.
std::vector<uint8_t> our_decode(const std::vector<uint8_t>& blocks, int W, int H, int channels) {
  std::vector<uint8_t> out(size_t(W) * H * channels);
  const int bw = W / 4;
  for (size_t b = 0; b < blocks.size() / (8 * channels); ++b)
    for (int c = 0; c < channels; ++c) {
      uint8_t v[16];
      bc4_decode_block_unorm8(&blocks[b * 8 * channels + c * 8], v);
      const int bx = int(b % bw), by = int(b / bw);
      for (int i = 0; i < 16; ++i) out[(size_t(by * 4 + i / 4) * W + bx * 4 + i % 4) * channels + c] = v[i];
    }
  return out;
}

using RgtcMesa = ahd_test::GlTest;

}  // namespace

TEST_F(RgtcMesa, RandomBlocksDecodeBitExact) {
  const int W = 512, H = 1024;  // 32768 blocks per texture
  std::mt19937 rng(99);
  for (int channels : {1, 2}) {
    size_t blocks_checked = 0, modes[2] = {0, 0};
    double worst = 0;  // Mesa's 8-bit values vs the exact palette, in 8-bit steps
    for (int round = 0; round < 4; ++round) {
      std::vector<uint8_t> blocks(size_t(W / 4) * (H / 4) * 8 * channels);
      for (auto& b : blocks) b = uint8_t(rng());
      for (size_t b = 0; b < blocks.size(); b += 8) {
        if (round == 3 && (b / 8) % 5 == 0) blocks[b + 1] = blocks[b];  // equal endpoints
        modes[blocks[b] > blocks[b + 1]]++;
      }
      const auto mesa = mesa_decode(channels == 1 ? GL_COMPRESSED_RED_RGTC1 : GL_COMPRESSED_RG_RGTC2, blocks, W, H, channels);
      const auto ours = our_decode(blocks, W, H, channels);
      size_t differ = 0;
      for (size_t i = 0; i < ours.size(); ++i) differ += ours[i] != mesa[i];
      ASSERT_EQ(differ, 0u) << "BC" << (channels == 1 ? 4 : 5) << " round " << round;
      // Mesa's values stay within one 8-bit step of the exact spec palette.
      for (size_t b = 0; b < blocks.size(); b += 8) {
        float exact[16];
        bc4_decode_block(&blocks[b], exact);
        uint8_t fixed[16];
        bc4_decode_block_unorm8(&blocks[b], fixed);
        for (int i = 0; i < 16; ++i) worst = std::max(worst, double(std::fabs(exact[i] * 255.0f - fixed[i])));
      }
      blocks_checked += blocks.size() / (8 * channels);
    }
    std::printf("BC%d: %zu random blocks bit-exact with Mesa (%zu 6-value-mode, %zu 8-value-mode halves)\n",
                channels == 1 ? 4 : 5, blocks_checked, modes[0], modes[1]);
    std::printf("  Mesa's fixed-point palette differs from the exact one by at most %.3f 8-bit steps\n", worst);
    EXPECT_LT(worst, 2.0);  // measured 1.6: truncated weights and 16-bit lanes
    EXPECT_GE(blocks_checked, 100000u);
    EXPECT_GT(modes[0], 10000u);
    EXPECT_GT(modes[1], 10000u);
  }
}

TEST_F(RgtcMesa, EncodedBlocksDecodeAsWeBelieve) {
  const int W = 256, H = 128;
  ImageF img(W, H, 2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      img.at(x, y)[0] = 0.5f + 0.5f * std::sin(x * 0.05f) * std::cos(y * 0.07f);
      img.at(x, y)[1] = (x + y) % 37 == 0 ? u(rng) : float(y) / H;
    }
  const std::vector<uint8_t> b5 = bc5_encode_image(img, 2);
  EXPECT_EQ(our_decode(b5, W, H, 2), mesa_decode(GL_COMPRESSED_RG_RGTC2, b5, W, H, 2));
  const std::vector<uint8_t> b4 = bc4_encode_image(img, 0, 2);
  EXPECT_EQ(our_decode(b4, W, H, 1), mesa_decode(GL_COMPRESSED_RED_RGTC1, b4, W, H, 1));
  // And Mesa's 8-bit decode is within one step of the exact palette our closed loop uses
  // (the known difference: llvmpipe interpolates in 8-bit fixed point, the spec in real numbers).
  const auto mesa = mesa_decode(GL_COMPRESSED_RED_RGTC1, b4, W, H, 1);
  ImageF exact(W, H, 1);
  bc4_decode_image(b4.data(), W, H, 8, 0, exact, 0);
  for (size_t i = 0; i < mesa.size(); ++i) ASSERT_LE(std::fabs(exact.data[i] * 255.0f - mesa[i]), 1.0f);
}

// BC6H decoder against Mesa's software GL (GL_ARB_texture_compression_bptc), bit for bit in half
// floats: random blocks of every mode (reserved ones included), unsigned and signed, and every
// block our encoder writes for the shared test images.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>

#include "codecs/bc6h/bc6h_codec.h"
#include "gl_fixture.h"
#include "image/image_io.h"

using namespace ahd;

namespace {

// Mesa's decode of W×H texels of blocks, as RGB half floats.
std::vector<uint16_t> mesa_decode(const std::vector<uint8_t>& blocks, int W, int H, bool is_signed) {
  GLuint tex;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glCompressedTexImage2D(GL_TEXTURE_2D, 0,
                         is_signed ? GL_COMPRESSED_RGB_BPTC_SIGNED_FLOAT : GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT, W, H, 0,
                         GLsizei(blocks.size()), blocks.data());
  std::vector<uint16_t> out(size_t(W) * H * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RGB, GL_HALF_FLOAT, out.data());
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  glDeleteTextures(1, &tex);
  return out;
}

// Counts texels whose 3 halves differ between ours and Mesa's.
size_t compare(const std::vector<uint8_t>& blocks, int W, int H, bool is_signed, std::string* example) {
  const std::vector<uint16_t> mesa = mesa_decode(blocks, W, H, is_signed);
  size_t differ = 0;
  const int bw = W / 4;
  for (size_t b = 0; b < blocks.size() / 16; ++b) {
    uint16_t ours[48];
    bc6h_decode_block(&blocks[b * 16], is_signed, ours);
    const int bx = int(b % bw), by = int(b / bw);
    for (int t = 0; t < 16; ++t) {
      const uint16_t* m = &mesa[(size_t(by * 4 + t / 4) * W + bx * 4 + t % 4) * 3];
      if (std::memcmp(m, &ours[t * 3], 6) != 0) {
        if (differ == 0 && example) {
          char buf[160];
          std::snprintf(buf, sizeof buf, "block %zu mode byte 0x%02x texel %d: ours %04x %04x %04x mesa %04x %04x %04x", b,
                        blocks[b * 16], t, ours[t * 3], ours[t * 3 + 1], ours[t * 3 + 2], m[0], m[1], m[2]);
          *example = buf;
        }
        ++differ;
      }
    }
  }
  return differ;
}

class Bc6hJudge : public ahd_test::GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    if (IsSkipped()) return;
    if (!ahd_test::has_gl_extension("GL_ARB_texture_compression_bptc")) GTEST_SKIP() << "no BPTC in this GL";
  }
};

}  // namespace

TEST_F(Bc6hJudge, RandomBlocksOfEveryModeDecodeBitExact) {
  const int W = 256, H = 256;  // 4096 blocks per upload
  const uint8_t codes[] = {0x00, 0x01, 0x02, 0x06, 0x0a, 0x0e, 0x12, 0x16, 0x1a, 0x1e, 0x03, 0x07, 0x0b, 0x0f,
                           0x13, 0x17, 0x1b, 0x1f};  // 14 modes + 4 reserved
  std::mt19937 rng(2024);
  for (bool is_signed : {false, true}) {
    size_t blocks_checked = 0;
    int per_mode[32] = {};
    for (int round = 0; round < 25; ++round) {
      std::vector<uint8_t> blocks(size_t(W / 4) * (H / 4) * 16);
      for (auto& b : blocks) b = uint8_t(rng());
      for (size_t b = 0; b < blocks.size(); b += 16) {
        const uint8_t code = codes[(b / 16 + round) % std::size(codes)];
        // Modes 0x00/0x01 use 2 mode bits; the rest 5.
        if (code < 2) blocks[b] = uint8_t((blocks[b] & ~0x03) | code);
        else blocks[b] = uint8_t((blocks[b] & ~0x1F) | code);
        per_mode[code]++;
      }
      std::string example;
      const size_t differ = compare(blocks, W, H, is_signed, &example);
      ASSERT_EQ(differ, 0u) << (is_signed ? "SF16" : "UF16") << ": " << example;
      blocks_checked += blocks.size() / 16;
    }
    std::printf("BC6H %s: %zu random blocks bit-exact with Mesa (every mode and the reserved codes)\n",
                is_signed ? "SF16" : "UF16", blocks_checked);
    EXPECT_GE(blocks_checked, 100000u);
    for (uint8_t c : codes) EXPECT_GT(per_mode[c], 1000) << "mode code " << int(c);
  }
}

TEST_F(Bc6hJudge, EveryBlockWeWriteForTheTestImagesDecodesAsWeBelieve) {
  for (const char* file : {"lightmap_smooth.exr", "hdr_hard.exr", "lightmap_noisy.exr"}) {
    const std::string path = std::string(AHD_TEST_DATA_DIR) + "/bc6h/" + file;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " missing (tests/data/README.md)";
    const ImageF src = read_image(path);
    for (bool is_signed : {false, true})
      for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default}) {
        Bc6hOptions o;
        o.is_signed = is_signed;
        o.quality = q;
        const std::vector<uint8_t> blocks = bc6h_encode_image(src, o);
        std::string example;
        EXPECT_EQ(compare(blocks, src.width, src.height, is_signed, &example), 0u)
            << file << " " << bc6h_quality_name(q) << ": " << example;
      }
    // `max` (its polish writes more 6-bit two-region blocks) on the 128² crop at (128, 128):
    // the whole images take minutes at this quality.
    ImageF crop(128, 128, src.channels);
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x)
        for (int c = 0; c < src.channels; ++c) crop.at(x, y)[c] = src.at(x + 128, y + 128)[c];
    for (bool is_signed : {false, true}) {
      Bc6hOptions o;
      o.is_signed = is_signed;
      o.quality = Bc6hQuality::Max;
      const std::vector<uint8_t> blocks = bc6h_encode_image(crop, o);
      std::string example;
      EXPECT_EQ(compare(blocks, 128, 128, is_signed, &example), 0u) << file << " max crop: " << example;
    }
  }
}

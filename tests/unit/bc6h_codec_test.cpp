// BC6H: header layouts, hard inputs (negatives, NaN, ±Inf, > 65504, 1e-7, one bright texel, pure
// gradients, odd sizes), determinism, independence of a block from its neighbours, fast paths =
// scalar. Accuracy on the shared images against the public encoders: tests/accuracy/bc6h_codec_test.cpp.
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <set>

#include "codecs/bc6h/bc6h_codec.h"
#include "codecs/bc6h/bc6h_fast.h"
#include "codecs/bc6h/bc6h_search_avx2.h"
#include "codecs/bc6h/bc6h_tables.h"
#include "core/cpu.h"
#include "image/image_io.h"
#include "sanitized.h"
#include "test_data.h"
#include "bc6h_fixture.h"

using namespace ahd;
using namespace ahd_fixture::bc6h_fixture;

TEST(Bc6h, HeaderLayoutsHaveTheSpecLengths) {
  for (int m = 0; m < bc6h::kModeCount; ++m) {
    const bc6h::ModeInfo& mi = bc6h::mode(m);
    const int mode_bits = mi.code < 2 ? 2 : 5;
    EXPECT_EQ(mode_bits + mi.layout_count, mi.regions == 2 ? 82 : 65) << "mode " << m;
    // Index bits fill the block exactly: 128 = header + 16·bits − anchors.
    EXPECT_EQ(mode_bits + mi.layout_count + 16 * mi.index_bits - mi.regions, 128) << "mode " << m;
  }
}

TEST(Bc6h, ReservedModesDecodeToZero) {
  for (uint8_t code : {0x13, 0x17, 0x1b, 0x1f}) {
    uint8_t blk[16];
    std::fill(blk, blk + 16, 0xFF);
    blk[0] = uint8_t(0xE0 | code);
    uint16_t out[48];
    bc6h_decode_block(blk, false, out);
    for (uint16_t h : out) EXPECT_EQ(h, 0);
  }
}

// One texel decoded alone is that texel of the whole block, for every mode (reserved ones too),
// partition and texel: random bits reach them all.
TEST(Bc6h, OneTexelDecodesAsItsBlock) {
  std::mt19937_64 rng(7);
  std::vector<std::array<uint8_t, 16>> blocks(20000);
  for (auto& b : blocks)
    for (int i = 0; i < 16; i += 8) {
      const uint64_t v = rng();
      std::memcpy(&b[i], &v, 8);
    }
  // Every mode code occurs: the two 2-bit ones and the sixteen 5-bit ones (4 of them reserved).
  std::set<int> codes;
  for (const auto& b : blocks) codes.insert((b[0] & 3) < 2 ? b[0] & 3 : b[0] & 0x1f);
  ASSERT_EQ(codes.size(), 18u);
  for (bool is_signed : {false, true}) {
    for (const auto& b : blocks) {
      uint16_t all[48];
      bc6h_decode_block(b.data(), is_signed, all);
      for (int t = 0; t < 16; ++t) {
        uint16_t one[3];
        bc6h_decode_texel(b.data(), is_signed, t, one);
        ASSERT_EQ(std::memcmp(one, &all[t * 3], sizeof one), 0) << "texel " << t << " signed " << is_signed;
      }
    }
  }
}

TEST(Bc6h, HardInputsNeverSpeckle) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  ImageF img(8, 8, 3);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0, 1);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = u(rng);
  img.at(0, 0)[0] = -5.0f;     // negative
  img.at(1, 0)[1] = nan;       // NaN
  img.at(2, 0)[2] = inf;       // +Inf
  img.at(3, 0)[0] = -inf;      // −Inf
  img.at(0, 1)[0] = 1e6f;      // beyond half max
  img.at(1, 1)[1] = 1e-7f;     // below half's normal range
  for (int c = 0; c < 3; ++c) img.at(6, 6)[c] = 3e4f;  // a single bright texel…
  for (int y = 4; y < 8; ++y)
    for (int x = 4; x < 8; ++x)
      if (x != 6 || y != 6)
        for (int c = 0; c < 3; ++c) img.at(x, y)[c] = 1e-3f;  // …in a dark block
  for (bool s : {false, true})
    for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default, Bc6hQuality::Max}) expect_sane(img, s, q, "hard 8x8");
  Bc6hStats st;
  Bc6hOptions o;
  bc6h_encode_image(img, o, &st);
  EXPECT_EQ(st.nan, 1u);
  EXPECT_EQ(st.inf, 2u);
  EXPECT_EQ(st.too_large, 1u);
  EXPECT_EQ(st.negative, 2u);  // −5 and −Inf→−65504→0
}

TEST(Bc6h, GradientsAndOddSizes) {
  // Pure gradients: every channel a function of one parameter (linear, and exponential over
  // 20 stops), horizontal on some sizes and vertical on others.
  for (auto [w, h] : {std::pair{1, 1}, {3, 5}, {4097, 3}, {16, 16}, {5, 37}}) {
    ImageF img(w, h, 3);
    const bool vertical = h > w;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float s = float(vertical ? y : x) / float(std::max(1, (vertical ? h : w) - 1));
        img.at(x, y)[0] = s * 100.0f;
        img.at(x, y)[1] = 0.5f * s + 0.01f;
        img.at(x, y)[2] = std::exp2(20.0f * s - 10.0f);
      }
    expect_sane(img, false, Bc6hQuality::Default, "gradient");
    expect_sane(img, false, Bc6hQuality::Fast, "gradient (fast)");  // padding of partial blocks
    Bc6hOptions o;
    o.threads = 1;
    const std::vector<uint8_t> b = bc6h_encode_image(img, o);
    const ImageF d = bc6h_decode_image(b.data(), w, h, false);
    const double e = log_rmse(img, d);
    std::printf("gradient %dx%d: log-RMSE %.4f\n", w, h, e);
    // 20 stops across 3 texels is beyond what one block's endpoints can hold precisely; the
    // longer ramps span at most 5 stops per block.
    if (std::max(w, h) >= 16) {
      EXPECT_LT(e, 0.05) << w << "x" << h;
    }
  }
}

TEST(Bc6h, DeterministicAndIndependentOfNeighbours) {
  ImageF img(64, 32, 3);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0, 1);
  for (float& v : img.data) v = std::exp2(16 * u(rng) - 8);
  // Under sanitizers `max` (a thousand times slower than `default`) runs on the left 32×16 texels
  // (8 × 4 blocks, block (5, 3) among them) instead of all 16 × 8 blocks.
  ImageF left(32, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c) left.at(x, y)[c] = img.at(x, y)[c];
  for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default, Bc6hQuality::High, Bc6hQuality::Max}) {
    const ImageF& im = q == Bc6hQuality::Max && ahd_test::kSanitized ? left : img;
    const int bw = im.width / 4, bh = im.height / 4;
    Bc6hOptions a;
    a.quality = q;
    a.threads = 1;
    Bc6hOptions b = a;
    b.threads = 2;
    const std::vector<uint8_t> one = bc6h_encode_image(im, a), two = bc6h_encode_image(im, b);
    EXPECT_EQ(one, two) << bc6h_quality_name(q);
    // Block (5, 3) encoded alone gives the same bytes as among its neighbours.
    ImageF alone(4, 4, 3);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) alone.at(x, y)[c] = im.at(20 + x, 12 + y)[c];
    const std::vector<uint8_t> single = bc6h_encode_image(alone, a);
    const size_t at = size_t(3 * bw + 5) * 16;
    EXPECT_TRUE(std::equal(single.begin(), single.end(), one.begin() + std::ptrdiff_t(at))) << bc6h_quality_name(q);
    // And every block through bc6h_encode_block (the one-block fit, where the image takes
    // `fast`'s and `default`'s fits from the eight-block batches) gives the image's bytes.
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx) {
        float rgb[48];
        const uint8_t valid[16] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
        for (int t = 0; t < 16; ++t)
          for (int c = 0; c < 3; ++c) rgb[t * 3 + c] = im.at(bx * 4 + t % 4, by * 4 + t / 4)[c];
        uint8_t blk[16];
        bc6h_encode_block(rgb, valid, false, q, blk);
        ASSERT_TRUE(std::equal(blk, blk + 16, one.begin() + std::ptrdiff_t((by * bw + bx) * 16)))
            << bc6h_quality_name(q) << " block " << bx << "," << by;
      }
  }
}

// Issue 28: `fast` and `default` encode a block equal to the one before it only once and copy
// its bytes; a copy must be exactly the block's own encoding, and a block that differs in one
// value, or only in which texels are real (the partial blocks of the right edge), is not a copy.
TEST(Bc6h, RepeatedBlocksGetTheirOwnBytes) {
  ImageF img(62, 16, 3);  // 16 × 4 blocks, the last column two texels wide
  std::mt19937 rng(28);
  std::uniform_real_distribution<float> u(0, 1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const int bx = x / 4, by = y / 4;
        float v = 0.02f;                                                          // flat gutter
        if (by == 1) v = 0.3f + 0.1f * float((x % 4) + 4 * (y % 4)) + 0.05f * c;  // a repeated ramp
        if (by == 2 && bx % 3 == 0) v = std::exp2(8 * u(rng) - 6);                // noise among flat blocks
        img.at(x, y)[c] = v;
      }
  img.at(4 * 7 + 2, 4 + 3)[1] += 0.5f;  // block (7, 1) differs from (6, 1) in one value
  for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default}) {
    Bc6hOptions o;
    o.quality = q;
    o.threads = 1;
    const std::vector<uint8_t> all = bc6h_encode_image(img, o);
    for (int by = 0; by < 4; ++by)
      for (int bx = 0; bx < 16; ++bx) {
        const int w = std::min(4, img.width - 4 * bx);
        ImageF alone(w, 4, 3);
        for (int y = 0; y < 4; ++y)
          for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) alone.at(x, y)[c] = img.at(4 * bx + x, 4 * by + y)[c];
        const std::vector<uint8_t> single = bc6h_encode_image(alone, o);
        ASSERT_TRUE(std::equal(single.begin(), single.end(), all.begin() + std::ptrdiff_t((by * 16 + bx) * 16)))
            << bc6h_quality_name(q) << " block " << bx << "," << by;
      }
    // The tweaked block is not its neighbour's copy.
    EXPECT_FALSE(std::equal(all.begin() + (16 + 6) * 16, all.begin() + (16 + 7) * 16, all.begin() + (16 + 7) * 16))
        << bc6h_quality_name(q);
  }
}

TEST(Bc6h, SignedKeepsNegativeValues) {
  ImageF img(4, 4, 3);
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) img.data[i * 3 + c] = i % 2 ? -2.5f : 1.25f + 0.25f * c;
  Bc6hOptions o;
  o.is_signed = true;
  const std::vector<uint8_t> b = bc6h_encode_image(img, o);
  const ImageF d = bc6h_decode_image(b.data(), 4, 4, true);
  // Signs survive; magnitudes within the precision of 10-bit endpoints in the half-bit domain.
  for (size_t i = 0; i < img.data.size(); ++i) EXPECT_NEAR(d.data[i], img.data[i], 0.05f * std::fabs(img.data[i])) << i;
  // The unsigned format cannot: negatives become 0 and are counted.
  Bc6hStats st;
  bc6h_encode_image(img, Bc6hOptions{}, &st);
  EXPECT_EQ(st.negative, 24u);
}

TEST(Bc6h, HalfConversionPathsGiveTheSameBits) {
  // Every finite half, the midpoints between neighbours (ties round to even), and random floats
  // over the whole half range: the F16C path (when this CPU has it) and the portable one agree,
  // and both equal Imath's conversion.
  std::vector<float> v;
  for (uint32_t bits = 0; bits < 0x7C00; ++bits) {
    Imath::half a, b;
    a.setBits(uint16_t(bits));
    b.setBits(uint16_t(bits + 1));
    v.push_back(float(a));
    v.push_back(-float(a));
    if (bits + 1 < 0x7C00) v.push_back(0.5f * (float(a) + float(b)));
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-26, 16);
  for (int i = 0; i < 100000; ++i) v.push_back(std::exp2(u(rng)));
  v.push_back(65504.0f);
  v.push_back(1e-30f);
  const int n = int(v.size());
  std::vector<uint16_t> portable(v.size()), dispatched(v.size());
  cpu::disable_for_tests(cpu::kF16c);
  bc6h::floats_to_half(v.data(), portable.data(), n);
  cpu::disable_for_tests(0);
  bc6h::floats_to_half(v.data(), dispatched.data(), n);
  std::printf("F16C on this CPU: %s\n", cpu::has(cpu::kF16c) ? "yes" : "no");
  for (int i = 0; i < n; ++i) {
    ASSERT_EQ(portable[i], Imath::half(v[i]).bits()) << v[i];
    ASSERT_EQ(dispatched[i], portable[i]) << v[i];
  }
}

TEST(Bc6h, SimdAndScalarLoopsWriteTheSameBytes) {
  // fast (the AVX-512 or AVX2 batches, or the one-block SSE2 loops), default (fast-fit blocks and searched ones), high
  // (two regions, 3-bit indices), unsigned and signed, on a crop of each shared image.
  for (const char* file : {"lightmap_smooth.exr", "hdr_hard.exr", "lightmap_noisy.exr"}) {
    const std::filesystem::path path = ahd_test::test_data("bc6h") / file;
    AHD_REQUIRE_DATA(path);
    const ImageF src = clamp_rgb(read_image(path.string()));
    const int side = ahd_test::kSanitized ? 48 : 96;  // 144 blocks under sanitizers, 576 otherwise
    ImageF crop(side, side, 3);
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x)
        for (int c = 0; c < 3; ++c) crop.at(x, y)[c] = src.at(x + 160, y + 160)[c];
    for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default, Bc6hQuality::High})
      for (bool is_signed : {false, true}) {
        Bc6hOptions o;
        o.quality = q;
        o.is_signed = is_signed;
        cpu::disable_for_tests(cpu::kAllSimd);
        const std::vector<uint8_t> scalar = bc6h_encode_image(crop, o);
        cpu::disable_for_tests(0);
        const std::vector<uint8_t> simd = bc6h_encode_image(crop, o);
        EXPECT_EQ(scalar, simd) << file << " " << bc6h_quality_name(q) << (is_signed ? " signed" : "");
        // The search's SSE2 index step and ranking, which AVX2 CPUs otherwise skip.
        cpu::disable_for_tests(cpu::kAboveSse2);
        const std::vector<uint8_t> sse2 = bc6h_encode_image(crop, o);
        cpu::disable_for_tests(0);
        EXPECT_EQ(scalar, sse2) << file << " " << bc6h_quality_name(q) << (is_signed ? " signed" : "") << " (SSE2)";
        cpu::disable_for_tests(cpu::kAboveAvx2);  // eight-block AVX2 batches where the CPU has AVX-512
        const std::vector<uint8_t> avx2 = bc6h_encode_image(crop, o);
        cpu::disable_for_tests(0);
        EXPECT_EQ(scalar, avx2) << file << " " << bc6h_quality_name(q) << (is_signed ? " signed" : "") << " AVX2";
      }
    // max (its polish evaluates candidates through the same index step) on a 32×32 corner (16×16
    // under sanitizers).
    const int corner = ahd_test::kSanitized ? 16 : 32;
    ImageF small(corner, corner, 3);
    for (int y = 0; y < corner; ++y)
      for (int x = 0; x < corner; ++x)
        for (int c = 0; c < 3; ++c) small.at(x, y)[c] = crop.at(x, y)[c];
    for (bool is_signed : {false, true}) {
      Bc6hOptions o;
      o.quality = Bc6hQuality::Max;
      o.is_signed = is_signed;
      cpu::disable_for_tests(cpu::kAllSimd);
      const std::vector<uint8_t> scalar = bc6h_encode_image(small, o);
      cpu::disable_for_tests(0);
      EXPECT_EQ(scalar, bc6h_encode_image(small, o)) << file << " max" << (is_signed ? " signed" : "");
      cpu::disable_for_tests(cpu::kAboveSse2);
      EXPECT_EQ(scalar, bc6h_encode_image(small, o)) << file << " max (SSE2)" << (is_signed ? " signed" : "");
      cpu::disable_for_tests(0);
    }
  }
}

TEST(Bc6h, FastPathWritesTheSameBytesWithEitherHalfConversion) {
  for (const char* file : {"lightmap_noisy.exr", "hdr_hard.exr"}) {
    const std::filesystem::path path = ahd_test::test_data("bc6h") / file;
    AHD_REQUIRE_DATA(path);
    const ImageF src = clamp_rgb(read_image(path.string()));
    Bc6hOptions o;
    o.quality = Bc6hQuality::Fast;
    cpu::disable_for_tests(cpu::kF16c);
    const std::vector<uint8_t> portable = bc6h_encode_image(src, o);
    cpu::disable_for_tests(0);
    EXPECT_EQ(portable, bc6h_encode_image(src, o)) << file;
  }
}

TEST(Bc6h, FastSolidBlocksAreExact) {
  // A solid block is written exactly (mode 14, endpoints ceil(64h/31)), from the darkest
  // subnormal to the largest half.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> bits(0, 0x7BFF);
  for (int i = 0; i < 2000; ++i) {
    const uint16_t hb[3] = {uint16_t(i == 0 ? 0x7BFF : bits(rng)), uint16_t(i == 1 ? 1 : bits(rng)), uint16_t(bits(rng))};
    ImageF img(4, 4, 3);
    for (int t = 0; t < 16; ++t)
      for (int c = 0; c < 3; ++c) {
        Imath::half h;
        h.setBits(hb[c]);
        img.data[t * 3 + c] = float(h);
      }
    Bc6hOptions o;
    o.quality = Bc6hQuality::Fast;
    const std::vector<uint8_t> b = bc6h_encode_image(img, o);
    uint16_t out[48];
    bc6h_decode_block(b.data(), false, out);
    for (int t = 0; t < 16; ++t)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(out[t * 3 + c], hb[c]) << i;
  }
}

TEST(Bc6h, RealLightmapsBeatBasisUniversal) {
  // The real-lightmap corpus (bench/data/real: I_z planes of two real Godot bakes, mostly dark and
  // smooth). Basis Universal measured side by side (scripts/peer-basis-bc6h.sh, docs/bc6h-real.md):
  // HQ 0.00079 / 0.00246, 9 modes / 32 patterns 0.00079 / 0.00245. `default`'s own bounds are
  // issue 28's measurements with the dark-block gates (0.000322 / 0.001671; before 0.00033 /
  // 0.00174) and max below default on a crop.
  const struct {
    const char* file;
    double basis_hq, basis_best, default_bound;
  } images[] = {{"godot-ragdoll-plain_iz_1024.exr", 0.00079, 0.00079, 0.000325},
                {"godot42-vermilion_iz.exr", 0.00246, 0.00245, 0.00168}};
  for (const auto& im : images) {
    const ImageF src = clamp_rgb(read_image(std::string(AHD_SOURCE_DIR) + "/bench/data/real/" + im.file));
    Bc6hOptions o;
    o.quality = Bc6hQuality::Fast;
    std::vector<uint8_t> b = bc6h_encode_image(src, o);
    const double fast = log_rmse(src, bc6h_decode_image(b.data(), src.width, src.height, false));
    o.quality = Bc6hQuality::Default;
    b = bc6h_encode_image(src, o);
    const double def = log_rmse(src, bc6h_decode_image(b.data(), src.width, src.height, false));
    std::printf("%s: fast %.6f (Basis HQ %.5f), default %.6f (Basis best %.5f)\n", im.file, fast, im.basis_hq, def,
                im.basis_best);
    EXPECT_LE(fast, im.basis_hq) << im.file;
    EXPECT_LE(def, im.basis_best) << im.file;
    EXPECT_LE(def, im.default_bound) << im.file;
    // A 96² crop with content (gutters and charts): SIMD and scalar paths write the same bytes,
    // and max is not worse than default there.
    ImageF crop(96, 96, 3);
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 96; ++x)
        for (int c = 0; c < 3; ++c) crop.at(x, y)[c] = src.at(x + 200, y + 200)[c];
    for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default}) {
      Bc6hOptions oq;
      oq.quality = q;
      cpu::disable_for_tests(cpu::kAllSimd);
      const std::vector<uint8_t> scalar = bc6h_encode_image(crop, oq);
      cpu::disable_for_tests(0);
      EXPECT_EQ(scalar, bc6h_encode_image(crop, oq)) << im.file << " " << bc6h_quality_name(q);
      cpu::disable_for_tests(cpu::kAboveAvx2);
      EXPECT_EQ(scalar, bc6h_encode_image(crop, oq)) << im.file << " " << bc6h_quality_name(q) << " AVX2";
      cpu::disable_for_tests(0);
    }
    ImageF small(32, 32, 3);
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x)
        for (int c = 0; c < 3; ++c) small.at(x, y)[c] = crop.at(x + 32, y + 32)[c];
    Bc6hOptions mx, od;
    mx.quality = Bc6hQuality::Max;
    const std::vector<uint8_t> bm = bc6h_encode_image(small, mx), bd = bc6h_encode_image(small, od);
    EXPECT_LE(log_rmse(small, bc6h_decode_image(bm.data(), 32, 32, false)),
              log_rmse(small, bc6h_decode_image(bd.data(), 32, 32, false)) * 1.0001)
        << im.file;
  }
}

TEST(Bc6h, DarkBlocksGetTwoRegionsInDefault) {
  // Issue 28: `default`'s two-region gates are errors in the judged metric, which shrinks with the
  // value below 1, so a dark block with two clusters (a chart edge: a lit pair of columns beside a
  // dim pair, values around 0.01) passed both gates untouched and kept the one-region fit of
  // `fast`. With the gates scaled for dark blocks (dark_gate_scale) it is searched and improves.
  float rgb[48];
  uint8_t valid[16];
  std::memset(valid, 1, 16);
  for (int t = 0; t < 16; ++t)
    for (int c = 0; c < 3; ++c)
      rgb[t * 3 + c] = 0.01f * ((t % 4) < 2 ? 0.8f + 0.05f * float(t / 4) + 0.1f * float(c) : 0.1f + 0.07f * float(c * (t / 4)));
  ImageF img(4, 4, 3);
  std::copy(rgb, rgb + 48, img.data.begin());
  double e[2];
  int k = 0;
  for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default}) {
    uint8_t out[16];
    bc6h_encode_block(rgb, valid, false, q, out);
    e[k++] = log_rmse(img, bc6h_decode_image(out, 4, 4, false));
  }
  std::printf("dark two-cluster block: fast %.3g, default %.3g\n", e[0], e[1]);
  EXPECT_LT(e[1], 0.8 * e[0]);
}

TEST(Bc6h, MaxIsNeverWorseThanDefaultOnAnyBlock) {
  // Issue 28: `max` lowest of all on every image. On the noisy image default's polished fast fit
  // beat max's search (0.04573 vs 0.04639), so max keeps default's block where it decodes closer.
  // Per block, in the judged metric (log2(1 + x) squared over the block's texels), on a 48² crop
  // of each shared image (tests/data/bc6h) and of each real lightmap.
  std::vector<std::string> files = {std::string(AHD_SOURCE_DIR) + "/bench/data/real/godot42-vermilion_iz.exr",
                                    std::string(AHD_SOURCE_DIR) + "/bench/data/real/godot-ragdoll-plain_iz_1024.exr"};
  for (const char* f : {"lightmap_smooth.exr", "hdr_hard.exr", "lightmap_noisy.exr"}) {
    const std::string path = std::string(AHD_TEST_DATA_DIR) + "/bc6h/" + f;
    if (std::ifstream(path)) files.push_back(path);
  }
  for (const std::string& file : files) {
    const ImageF src = clamp_rgb(read_image(file));
    ImageF crop(48, 48, 3);
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x)
        for (int c = 0; c < 3; ++c) crop.at(x, y)[c] = src.at(x + 232, y + 232)[c];
    Bc6hOptions mx, od;
    mx.quality = Bc6hQuality::Max;
    const std::vector<uint8_t> bm = bc6h_encode_image(crop, mx), bd = bc6h_encode_image(crop, od);
    const ImageF dm = bc6h_decode_image(bm.data(), 48, 48, false), dd = bc6h_decode_image(bd.data(), 48, 48, false);
    int better = 0;
    for (int by = 0; by < 12; ++by)
      for (int bx = 0; bx < 12; ++bx) {
        double em = 0, ed = 0;
        for (int t = 0; t < 16; ++t)
          for (int c = 0; c < 3; ++c) {
            const int x = bx * 4 + t % 4, y = by * 4 + t / 4;
            const double l = std::log2(1.0 + double(crop.at(x, y)[c]));
            em += std::pow(std::log2(1.0 + double(dm.at(x, y)[c])) - l, 2);
            ed += std::pow(std::log2(1.0 + double(dd.at(x, y)[c])) - l, 2);
          }
        EXPECT_LE(em, ed * (1 + 1e-6) + 1e-12) << file << " block " << bx << "," << by;
        better += em < ed;
      }
    std::printf("%s: max below default on %d of 144 blocks\n", file.c_str(), better);
  }
}

TEST(Bc6h, FastIgnoresPaddingTexels) {
  // Texels marked invalid (the padding of partial blocks) neither fit nor cap the block: any
  // values there give the same bytes as the edge replication the image path uses.
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < 200; ++i) {
    float a[48], b[48];
    uint8_t valid[16];
    for (int t = 0; t < 16; ++t) valid[t] = (t % 4) < 1 + i % 4 && (t / 4) < 1 + (i / 4) % 4;
    for (int k = 0; k < 48; ++k) a[k] = b[k] = std::exp2(12 * u(rng) - 6);
    for (int t = 0; t < 16; ++t)
      if (!valid[t])
        for (int c = 0; c < 3; ++c) a[t * 3 + c] = a[c], b[t * 3 + c] = 60000.0f * u(rng);
    uint8_t oa[16], ob[16];
    bc6h_encode_block(a, valid, false, Bc6hQuality::Fast, oa);
    bc6h_encode_block(b, valid, false, Bc6hQuality::Fast, ob);
    ASSERT_TRUE(std::equal(oa, oa + 16, ob)) << i;
  }
}

TEST(Bc6h, FastBatchedBlocksAreTheBlocksEncodedAlone) {
  // The AVX2 path encodes eight blocks per batch, one per lane; the AVX-512 path sixteen, eight
  // batches per call, the second pass's index step on lanes gathered from all eight. A block's
  // bytes must not depend on the other blocks of its batch (PEERS.md: a batched peer encoder got this wrong): random
  // blocks of many kinds — solid, partial (padding texels), gradients, a wide range of values,
  // one bright texel — encoded alone, in mixed batches of every offset, and with the one-block
  // scalar path forced, must give the same bytes.
  // The same holds for the AVX-512 path's sixteen-block batches, and with the AVX2 path forced
  // on a CPU that has AVX-512.
  std::printf("AVX2 on this CPU: %s, AVX-512: %s\n", cpu::has(cpu::kAvx2) ? "yes" : "no",
              cpu::has(cpu::kAvx512) ? "yes" : "no");
  constexpr int kBlocks = 203;  // not a multiple of 8: the last batch is partial
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<float> x(kBlocks * 48);
  std::vector<uint16_t> h(kBlocks * 48);
  std::vector<uint8_t> valid(kBlocks * 16, 1);
  for (int b = 0; b < kBlocks; ++b) {
    float* v = &x[b * 48];
    const int kind = b % 6;
    const float scale = std::exp2(24 * u(rng) - 12);
    for (int t = 0; t < 16; ++t)
      for (int c = 0; c < 3; ++c) {
        float val = scale * std::exp2(4 * u(rng) - 2);                                // noisy
        if (kind == 1) val = scale * (1 + c);                                          // solid
        if (kind == 2) val = scale * (1 + 0.1f * float(t) + 0.05f * float(c));         // gradient
        if (kind == 3 && t == 5) val = 64 * scale;                                     // one bright texel
        if (kind == 4) val = std::exp2(32 * u(rng) - 16);                              // any range
        v[t * 3 + c] = std::min(val, 65504.0f);
      }
    if (kind == 5)  // a partial edge block: padding texels repeat the first one
      for (int t = 0; t < 16; ++t)
        if (t % 4 >= 1 + b % 4 || t / 4 >= 1 + (b / 4) % 4) {
          valid[b * 16 + t] = 0;
          for (int c = 0; c < 3; ++c) v[t * 3 + c] = v[c];
        }
  }
  bc6h::floats_to_half(x.data(), h.data(), kBlocks * 48);
  std::vector<uint8_t> alone(kBlocks * 16), scalar(kBlocks * 16);
  for (int b = 0; b < kBlocks; ++b) bc6h::encode_blocks_fast(&h[b * 48], &x[b * 48], &valid[b * 16], 1, &alone[b * 16]);
  cpu::disable_for_tests(cpu::kAllSimd);
  bc6h::encode_blocks_fast(h.data(), x.data(), valid.data(), kBlocks, scalar.data());
  cpu::disable_for_tests(0);
  EXPECT_EQ(alone, scalar);
  for (int b = 0; b < kBlocks; ++b) {  // the one-block encoder itself
    uint8_t one[16];
    bc6h::encode_block_fast(&h[b * 48], &x[b * 48], &valid[b * 16], one);
    ASSERT_TRUE(std::equal(one, one + 16, &scalar[b * 16])) << b;
  }
  for (bool avx2 : {false, true}) {
    SCOPED_TRACE(avx2 ? "AVX2 forced" : "widest batches");
    cpu::disable_for_tests(avx2 ? cpu::kAboveAvx2 : 0);
    // The fits themselves (`default` starts from them and reads their error against a threshold):
    // batched fits equal the one-block fits field by field, the error bit for bit.
    std::vector<bc6h::OneRegionFit> fits(kBlocks);
    bc6h::fit_blocks_fast(h.data(), x.data(), valid.data(), kBlocks, fits.data());
    for (int b = 0; b < kBlocks; ++b) {
      bc6h::OneRegionFit one;
      bc6h::fit_one_region_fast(&h[b * 48], &x[b * 48], &valid[b * 16], &one);
      ASSERT_EQ(fits[b].mode, one.mode) << b;
      for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(fits[b].e[k][c], one.e[k][c]) << b;
      ASSERT_TRUE(std::equal(one.idx, one.idx + 16, fits[b].idx)) << b;
      ASSERT_EQ(std::bit_cast<uint32_t>(fits[b].err), std::bit_cast<uint32_t>(one.err)) << b << " " << one.err;
    }
    for (int offset = 0; offset < 16; ++offset) {  // every block in every lane position
      std::vector<uint8_t> batched((kBlocks - offset) * 16);
      bc6h::encode_blocks_fast(&h[offset * 48], &x[offset * 48], &valid[offset * 16], kBlocks - offset, batched.data());
      EXPECT_TRUE(std::equal(batched.begin(), batched.end(), alone.begin() + offset * 16)) << "offset " << offset;
    }
    // Shuffled batches: each block among different neighbours.
    std::vector<int> order(kBlocks);
    for (int b = 0; b < kBlocks; ++b) order[b] = b;
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<float> xs(kBlocks * 48);
    std::vector<uint16_t> hs(kBlocks * 48);
    std::vector<uint8_t> vs(kBlocks * 16), shuffled(kBlocks * 16);
    for (int i = 0; i < kBlocks; ++i) {
      std::copy_n(&x[order[i] * 48], 48, &xs[i * 48]);
      std::copy_n(&h[order[i] * 48], 48, &hs[i * 48]);
      std::copy_n(&valid[order[i] * 16], 16, &vs[i * 16]);
    }
    bc6h::encode_blocks_fast(hs.data(), xs.data(), vs.data(), kBlocks, shuffled.data());
    for (int i = 0; i < kBlocks; ++i)
      ASSERT_TRUE(std::equal(&shuffled[i * 16], &shuffled[i * 16] + 16, &alone[order[i] * 16])) << order[i];
    cpu::disable_for_tests(0);
  }
  // And the blocks decode within the no-specks bound.
  for (int b = 0; b < kBlocks; ++b) {
    uint16_t dec[48];
    bc6h_decode_block(&alone[b * 16], false, dec);
    for (int c = 0; c < 3; ++c) {
      int top = 0;
      for (int t = 0; t < 16; ++t)
        if (valid[b * 16 + t]) top = std::max(top, int(h[b * 48 + t * 3 + c]));
      for (int t = 0; t < 16; ++t) ASSERT_LE(int(dec[t * 3 + c]), top + 1) << b;
    }
  }
  // The blocks above include ones the two-region candidate wrote (so the comparisons above
  // cover it): a one-region block's 5 mode bits are 0x03, 0x07, 0x0B or 0x0F.
  int two_region = 0;
  for (int b = 0; b < kBlocks; ++b) {
    const int code = alone[b * 16] & 0x1F;
    two_region += code != 0x03 && code != 0x07 && code != 0x0B && code != 0x0F;
  }
  std::printf("two-region blocks: %d of %d\n", two_region, kBlocks);
  EXPECT_GT(two_region, 0);
}

namespace {

// The weighted squared error in half steps (the fast fit's measure) of a decoded block.
double fast_measure(const uint16_t h[48], const float x[48], const uint16_t dec[48]) {
  double e = 0;
  for (int i = 0; i < 48; ++i) {
    const double v = std::max(x[i], 0.25f), s = v / (1 + v), d = double(dec[i]) - double(h[i]);
    e += s * s * d * d;
  }
  return e;
}

}  // namespace

TEST(Bc6h, FastTwoRegionLanesWriteTheScalarBytes) {
  // The two-region candidate's AVX-512 index step and axis targets (one partition region per
  // lane, sums masked by region and validity) against its scalar loops, on blocks made for it:
  // two clusters on a random partition with noise, every other block partial — some with a region
  // that has no valid texel, some with a single valid texel. Same bytes, the no-specks bound, and
  // the candidate must win on most of them (else this would not test it). Blocks b % 4 < 2 have
  // clusters up to 2^12 apart (mostly the edge route: one partition, the brightness split), the
  // others within 2^3 (the ranked search over eight partitions in the lanes).
  constexpr int kBlocks = 96;
  std::mt19937 rng(1313);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<float> x(kBlocks * 48);
  std::vector<uint16_t> h(kBlocks * 48);
  std::vector<uint8_t> valid(kBlocks * 16, 1);
  for (int b = 0; b < kBlocks; ++b) {
    const unsigned part = bc6h::kPartitions[rng() % 32];
    float colour[2][3];
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 3; ++c) colour[r][c] = std::exp2(b % 4 < 2 ? 12 * u(rng) - 4 : 3 * u(rng));
    for (int t = 0; t < 16; ++t) {
      const int r = (part >> t) & 1;
      const float n = std::exp2(0.6f * u(rng) - 0.3f);
      for (int c = 0; c < 3; ++c) x[b * 48 + t * 3 + c] = std::min(colour[r][c] * n, 65504.0f);
    }
    if (b % 2) {  // partial: a random valid mask (region 1 only, one texel, or random)
      const int kind = (b / 2) % 3;
      for (int t = 0; t < 16; ++t) {
        const bool keep = kind == 0 ? ((part >> t) & 1) != 0 : kind == 1 ? t == int(rng() % 16) || t == 15 : u(rng) < 0.5f;
        valid[b * 16 + t] = keep ? 1 : 0;
      }
      valid[b * 16 + 15] = 1;  // texel 15 is in region 1 of every partition: never empty
      int first = 0;
      while (!valid[b * 16 + first]) ++first;
      for (int t = 0; t < 16; ++t)
        if (!valid[b * 16 + t])
          for (int c = 0; c < 3; ++c) x[b * 48 + t * 3 + c] = x[b * 48 + first * 3 + c];
    }
  }
  bc6h::floats_to_half(x.data(), h.data(), kBlocks * 48);
  std::vector<uint8_t> wide(kBlocks * 16), scalar(kBlocks * 16);
  bc6h::encode_blocks_fast(h.data(), x.data(), valid.data(), kBlocks, wide.data());
  cpu::disable_for_tests(cpu::kAllSimd);
  bc6h::encode_blocks_fast(h.data(), x.data(), valid.data(), kBlocks, scalar.data());
  cpu::disable_for_tests(0);
  int two_region = 0;
  for (int b = 0; b < kBlocks; ++b) {
    ASSERT_TRUE(std::equal(&wide[b * 16], &wide[b * 16] + 16, &scalar[b * 16])) << b;
    const int code = wide[b * 16] & 0x1F;
    two_region += code != 0x03 && code != 0x07 && code != 0x0B && code != 0x0F;
    uint16_t dec[48];
    bc6h_decode_block(&wide[b * 16], false, dec);
    for (int c = 0; c < 3; ++c) {
      int top = 0;
      for (int t = 0; t < 16; ++t)
        if (valid[b * 16 + t]) top = std::max(top, int(h[b * 48 + t * 3 + c]));
      for (int t = 0; t < 16; ++t) ASSERT_LE(int(dec[t * 3 + c]), top + 1) << b;
    }
  }
  std::printf("AVX-512: %s; two-region blocks: %d of %d\n", cpu::has(cpu::kAvx512) ? "yes" : "no", two_region, kBlocks);
  EXPECT_GT(two_region, kBlocks / 3);
}

TEST(Bc6h, FastTwoClustersGetTwoRegions) {
  // Two clusters that no one line follows (the top half varies along grey, the bottom half
  // along red): `fast` writes a two-region block, lower in its error measure than the one-region
  // fit, in the no-specks bound, and the same with the scalar path forced.
  float x[48];
  uint16_t h[48];
  const uint8_t valid[16] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  for (int t = 0; t < 16; ++t) {
    const float s = std::exp2(float((t * 7) % 8) * 0.5f - 2);  // 0.25 … 2.8, shuffled
    for (int c = 0; c < 3; ++c) x[t * 3 + c] = t < 8 ? s : (c == 0 ? 16 * s : 4.0f);
  }
  bc6h::floats_to_half(x, h, 48);
  uint8_t out[16], scalar[16], one[16];
  bc6h::encode_blocks_fast(h, x, valid, 1, out);
  cpu::disable_for_tests(cpu::kAllSimd);
  bc6h::encode_blocks_fast(h, x, valid, 1, scalar);
  cpu::disable_for_tests(0);
  EXPECT_TRUE(std::equal(out, out + 16, scalar));
  const int code = out[0] & 0x1F;
  EXPECT_TRUE(code != 0x03 && code != 0x07 && code != 0x0B && code != 0x0F) << "mode bits " << code;
  bc6h::OneRegionFit fit;
  bc6h::fit_one_region_fast(h, x, valid, &fit);  // the one-region fit alone
  bc6h::pack_one_region(fit, one);
  uint16_t dec[48], dec_one[48];
  bc6h_decode_block(out, false, dec);
  bc6h_decode_block(one, false, dec_one);
  const double e2 = fast_measure(h, x, dec), e1 = fast_measure(h, x, dec_one);
  std::printf("one region %.0f, written %.0f\n", e1, e2);
  EXPECT_LT(e2, 0.5 * e1);
  for (int c = 0; c < 3; ++c) {
    int top = 0;
    for (int t = 0; t < 16; ++t) top = std::max(top, int(h[t * 3 + c]));
    for (int t = 0; t < 16; ++t) EXPECT_LE(int(dec[t * 3 + c]), top + 1) << t;
  }
}

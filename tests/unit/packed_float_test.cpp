// Half, RGB9E5 and B10G11R11 against the spec's edge cases: max finite, just over max, Inf, NaN,
// negative, −0, denormals, rounding ties, and every representable value round-tripping.
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <cmath>
#include <limits>

#include "codecs/packed_float.h"

using namespace ahd;

namespace {
const float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();
}  // namespace

TEST(PackedFloat, Float11And10RoundTripEveryFiniteValue) {
  for (int mbits : {6, 5}) {
    for (uint32_t v = 0; v < (31u << mbits); ++v) {
      const float f = small_ufloat_to_float(v, mbits);
      ASSERT_TRUE(std::isfinite(f));
      ASSERT_EQ(float_to_small_ufloat(f, mbits), v) << "mbits " << mbits << " code " << v << " value " << f;
    }
  }
}

TEST(PackedFloat, Float11EdgeCases) {
  EXPECT_EQ(small_ufloat_to_float((30u << 6) | 63u, 6), kFloat11Max);
  EXPECT_EQ(small_ufloat_to_float((30u << 5) | 31u, 5), kFloat10Max);
  EXPECT_EQ(small_ufloat_to_float(31u << 6, 6), kInf);
  EXPECT_TRUE(std::isnan(small_ufloat_to_float((31u << 6) | 1u, 6)));
  PackStats st;
  EXPECT_EQ(float_to_small_ufloat(70000.0f, 6, &st), (30u << 6) | 63u);  // too large → max finite
  EXPECT_EQ(float_to_small_ufloat(kInf, 6, &st), (30u << 6) | 63u);
  EXPECT_EQ(float_to_small_ufloat(kNaN, 6, &st), 0u);
  EXPECT_EQ(float_to_small_ufloat(-1.0f, 6, &st), 0u);
  EXPECT_EQ(float_to_small_ufloat(-0.0f, 6, &st), 0u);
  EXPECT_EQ(st.too_large, 1u);
  EXPECT_EQ(st.non_finite, 2u);
  EXPECT_EQ(st.negative, 1u);
  // Denormals: smallest 2^-20 (11-bit) and 2^-19 (10-bit); largest denormal 63·2^-20.
  EXPECT_EQ(float_to_small_ufloat(std::ldexp(1.0f, -20), 6), 1u);
  EXPECT_EQ(float_to_small_ufloat(std::ldexp(1.0f, -19), 5), 1u);
  EXPECT_EQ(float_to_small_ufloat(63 * std::ldexp(1.0f, -20), 6), 63u);
  // Ties round to even: 1 + 1/128 lies halfway between 1 and 1 + 1/64 (mantissa 0 is even).
  EXPECT_EQ(float_to_small_ufloat(1.0f + 1.0f / 128, 6), 15u << 6);
  // 1 + 3/128 lies halfway between mantissa 1 and 2: even is 2.
  EXPECT_EQ(float_to_small_ufloat(1.0f + 3.0f / 128, 6), (15u << 6) | 2u);
  // Half of the smallest denormal ties to 0; 1.5 × rounds to 2.
  EXPECT_EQ(float_to_small_ufloat(std::ldexp(1.0f, -21), 6), 0u);
  EXPECT_EQ(float_to_small_ufloat(3 * std::ldexp(1.0f, -21), 6), 2u);
  // Rounding up out of the denormal range gives the smallest normal.
  EXPECT_EQ(float_to_small_ufloat(63.5f * std::ldexp(1.0f, -20), 6), 1u << 6);
  // Channel placement: R bits 0–10, G 11–21, B 22–31.
  EXPECT_EQ(pack_b10g11r11(1.0f, 0, 0), 15u << 6);
  EXPECT_EQ(pack_b10g11r11(0, 1.0f, 0), (15u << 6) << 11);
  EXPECT_EQ(pack_b10g11r11(0, 0, 1.0f), (15u << 5) << 22);
}

TEST(PackedFloat, Rgb9e5EdgeCases) {
  float rgb[3];
  unpack_rgb9e5(0xFFFFFFFFu, rgb);
  EXPECT_EQ(rgb[0], kRgb9e5Max);
  PackStats st;
  EXPECT_EQ(pack_rgb9e5(kRgb9e5Max, 0, 0, &st), 511u | 31u << 27);
  EXPECT_EQ(pack_rgb9e5(1e6f, 0, 0, &st), 511u | 31u << 27);  // too large → max
  EXPECT_EQ(pack_rgb9e5(kInf, kNaN, -2.0f, &st), 511u | 31u << 27);
  EXPECT_EQ(st.too_large, 1u);
  EXPECT_EQ(st.non_finite, 2u);
  EXPECT_EQ(st.negative, 1u);
  EXPECT_EQ(pack_rgb9e5(0, 0, 0), 0u);
  EXPECT_EQ(pack_rgb9e5(-0.0f, 0, 0), 0u);
  // 1.0: exponent chosen so that max_s fits 9 bits: 1 = 256 · 2^(16−15−9).
  EXPECT_EQ(pack_rgb9e5(1.0f, 0, 0), 256u | 16u << 27);
  // The exponent bump: 511.75/512 · 2 rounds to 512 mantissa → the next exponent, mantissa 256.
  EXPECT_EQ(pack_rgb9e5(2.0f * 511.75f / 512.0f, 0, 0), 256u | 17u << 27);
  // Smallest non-zero: 2^-24 (e = 0, mantissa 1); half of it ties to even (0 … but floor(x+0.5)
  // of the spec rounds half up: 0.5 → 1).
  EXPECT_EQ(pack_rgb9e5(std::ldexp(1.0f, -24), 0, 0), 1u);
  EXPECT_EQ(pack_rgb9e5(std::ldexp(1.0f, -25), 0, 0), 1u);
  // Shared exponent: the small channel loses precision relative to the large one.
  unpack_rgb9e5(pack_rgb9e5(1000.0f, 1.0f, 0.001f), rgb);
  EXPECT_NEAR(rgb[0], 1000.0f, 1.0f);
  EXPECT_NEAR(rgb[1], 1.0f, 2.0f);
  EXPECT_EQ(rgb[2], 0.0f);
  // Every mantissa at every exponent round-trips.
  for (uint32_t e = 0; e < 32; ++e)
    for (uint32_t m = 256; m < 512; ++m) {
      const uint32_t v = m | e << 27;
      unpack_rgb9e5(v, rgb);
      ASSERT_EQ(pack_rgb9e5(rgb[0], 0, 0), v) << e << " " << m;
    }
}

TEST(PackedFloat, HalfFollowsIeee) {
  EXPECT_EQ(Imath::half(65504.0f).bits(), 0x7BFFu);
  EXPECT_EQ(Imath::half(65520.0f).bits(), 0x7C00u);  // ties above max round to Inf: why we clamp first
  EXPECT_EQ(Imath::half(std::ldexp(1.0f, -24)).bits(), 0x0001u);
  EXPECT_EQ(Imath::half(1.0f + std::ldexp(1.0f, -11)).bits(), 0x3C00u);  // tie to even
  EXPECT_EQ(Imath::half(1.0f + 3 * std::ldexp(1.0f, -11)).bits(), 0x3C02u);
  EXPECT_EQ(Imath::half(-0.0f).bits(), 0x8000u);
}

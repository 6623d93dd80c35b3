// Packed HDR texel formats, exact to the Vulkan/OpenGL rules:
//   E5B9G9R9_UFLOAT (DXGI R9G9B9E5_SHAREDEXP): three 9-bit mantissas, one shared 5-bit exponent.
//   B10G11R11_UFLOAT (DXGI R11G11B10_FLOAT): 11-bit R (bits 0–10), 11-bit G (11–21), 10-bit B
//     (22–31) unsigned floats, 5-bit exponent (bias 15), 6/6/5-bit mantissas, denormals.
// Rounding is round-to-nearest-even. Inputs the formats cannot hold follow one documented rule,
// counted in PackStats: negative → 0, NaN → 0, +Inf and values above the largest finite value →
// the largest finite value (RGB9E5 has no Inf/NaN; for 11/10-bit floats a lightmap must not
// decode to Inf or NaN either).
#pragma once
#include <cstddef>
#include <cstdint>

namespace ahd {

struct PackStats {
  size_t negative = 0;    // clamped to 0 (−0 is not counted)
  size_t non_finite = 0;  // NaN → 0, +Inf → max
  size_t too_large = 0;   // finite values above the format's max → max
};

constexpr float kRgb9e5Max = 65408.0f;     // 511/512 · 2^16
constexpr float kFloat11Max = 65024.0f;    // (1 + 63/64) · 2^15
constexpr float kFloat10Max = 64512.0f;    // (1 + 31/32) · 2^15

uint32_t pack_rgb9e5(float r, float g, float b, PackStats* stats = nullptr);
void unpack_rgb9e5(uint32_t v, float rgb[3]);

uint32_t pack_b10g11r11(float r, float g, float b, PackStats* stats = nullptr);
void unpack_b10g11r11(uint32_t v, float rgb[3]);

// One unsigned small float: `mantissa_bits` 6 (11-bit float) or 5 (10-bit float), 5-bit exponent.
// Round to nearest even by default; `toward_zero` gives the truncation the GL spec also allows
// (and Mesa uses), for the tests that compare with it.
uint32_t float_to_small_ufloat(float f, int mantissa_bits, PackStats* stats = nullptr, bool toward_zero = false);
float small_ufloat_to_float(uint32_t v, int mantissa_bits);

}  // namespace ahd

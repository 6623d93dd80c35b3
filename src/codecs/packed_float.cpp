#include "codecs/packed_float.h"

#include <algorithm>
#include <cmath>

namespace ahd {
namespace {

// The clamping rule shared by both formats; returns a finite value in [0, max].
float sanitise(float f, float max, PackStats* st) {
  if (std::isnan(f)) {
    if (st) st->non_finite++;
    return 0.0f;
  }
  if (f < 0.0f) {
    if (st) st->negative++;
    return 0.0f;
  }
  if (f > max) {
    if (st) (std::isinf(f) ? st->non_finite : st->too_large)++;
    return max;
  }
  return f;  // also maps −0 to itself, which encodes as +0
}

}  // namespace

uint32_t pack_rgb9e5(float r, float g, float b, PackStats* st) {
  // The shared-exponent algorithm of the spec (EXT_texture_shared_exponent, Vulkan §"Shared
  // Exponent"): N = 9, B = 15, Emax = 31.
  constexpr int N = 9, B = 15;
  const double rc = sanitise(r, kRgb9e5Max, st), gc = sanitise(g, kRgb9e5Max, st), bc = sanitise(b, kRgb9e5Max, st);
  const double maxc = std::max({rc, gc, bc});
  int fl = -B - 1;
  if (maxc > 0) {
    fl = int(std::floor(std::log2(maxc)));
    // log2 of a value just under a power of two can round up; the spec's floor is exact.
    if (std::ldexp(1.0, fl) > maxc) --fl;
  }
  const int exp_p = std::max(-B - 1, fl) + 1 + B;
  const double max_s = std::floor(maxc / std::ldexp(1.0, exp_p - B - N) + 0.5);
  const int e = max_s == double(1 << N) ? exp_p + 1 : exp_p;
  const double scale = std::ldexp(1.0, e - B - N);
  auto m = [&](double c) { return uint32_t(std::floor(c / scale + 0.5)); };
  return m(rc) | m(gc) << 9 | m(bc) << 18 | uint32_t(e) << 27;
}

void unpack_rgb9e5(uint32_t v, float rgb[3]) {
  const int e = int(v >> 27);
  const double scale = std::ldexp(1.0, e - 15 - 9);
  rgb[0] = float((v & 0x1FF) * scale);
  rgb[1] = float(((v >> 9) & 0x1FF) * scale);
  rgb[2] = float(((v >> 18) & 0x1FF) * scale);
}

uint32_t float_to_small_ufloat(float f, int mbits, PackStats* st, bool toward_zero) {
  const float max = mbits == 6 ? kFloat11Max : kFloat10Max;
  const double x = sanitise(f, max, st);
  if (x == 0.0) return 0;
  int e2;
  const double frac = std::frexp(x, &e2);  // x = frac · 2^e2, frac in [0.5, 1)
  const int exp = e2 - 1;                  // x = (1.f) · 2^exp
  const uint32_t one = 1u << mbits;
  if (exp < -14) {
    // Denormal: x = m · 2^(−14 − mbits), rounded to nearest even. m may round up to `one`,
    // which is exactly the encoding of the smallest normal value.
    const double m = std::ldexp(x, 14 + mbits);
    return uint32_t(toward_zero ? std::floor(m) : std::nearbyint(m));
  }
  const double mf = (frac * 2.0 - 1.0) * one;
  uint32_t m = uint32_t(toward_zero ? std::floor(mf) : std::nearbyint(mf));
  int be = exp + 15;
  if (m == one) m = 0, ++be;
  if (be >= 31) return (30u << mbits) | (one - 1);  // unreachable after sanitise, kept for safety
  return uint32_t(be) << mbits | m;
}

float small_ufloat_to_float(uint32_t v, int mbits) {
  const uint32_t e = v >> mbits, m = v & ((1u << mbits) - 1);
  if (e == 0) return float(std::ldexp(double(m), -14 - mbits));
  if (e == 31) return m ? NAN : INFINITY;
  return float(std::ldexp(1.0 + double(m) / double(1u << mbits), int(e) - 15));
}

uint32_t pack_b10g11r11(float r, float g, float b, PackStats* st) {
  return float_to_small_ufloat(r, 6, st) | float_to_small_ufloat(g, 6, st) << 11 | float_to_small_ufloat(b, 5, st) << 22;
}

void unpack_b10g11r11(uint32_t v, float rgb[3]) {
  rgb[0] = small_ufloat_to_float(v & 0x7FF, 6);
  rgb[1] = small_ufloat_to_float((v >> 11) & 0x7FF, 6);
  rgb[2] = small_ufloat_to_float(v >> 22, 5);
}

}  // namespace ahd

// The inner loop of every error figure (fit/hemisphere_error.h): one texel's lobe against its SH
// over the hemisphere directions — squared error, squared log2 ratio and luminance, summed. Internal
// to src/fit. Three paths, the plain one, AVX2 (four directions at a time) and AVX-512 (eight); all
// run the same IEEE operations in the same order for every direction and sum in the same four
// lanes, so they give the same bits (test HemisphereSums.PathsGiveTheSameBits).
#pragma once
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "fit/hemisphere_error.h"
#include "sh/sh.h"

namespace ahd {

// Rec. 709 luminance weights of the relative figure.
inline constexpr double kLumaWeights[3] = {0.2126, 0.7152, 0.0722};

// Over directions w_k = dirs[3k..3k+2], k < n, and channels c:
//   se  = Σ (got − ref)²,   lum = Σ luma_c · ref,   sl = Σ log2((1 + got⁺) / (1 + ref⁺))²  (with_log),
// ref = E_c(w_k) (eval_irradiance), got = ca_c + max(0, w_k·d) cd_c. Summed in four lanes
// (direction k in lane k mod 4, channels in order), the lanes then as (l0 + l1) + (l2 + l3).
struct HemisphereSums {
  double se = 0, sl = 0, lum = 0;
};
HemisphereSums hemisphere_sums(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n, bool with_log);

// The three paths (tests force each): plain, AVX2 (call only when cpu::has(cpu::kAvx2)) and
// AVX-512 (only when cpu::has(cpu::kAvx2 | cpu::kAvx512)).
HemisphereSums hemisphere_sums_plain(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n,
                                     bool with_log);
HemisphereSums hemisphere_sums_avx2(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n,
                                    bool with_log);
HemisphereSums hemisphere_sums_avx512(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n,
                                      bool with_log);

// log2(x) as 2·atanh((m − 1)/(m + 1))·log2(e) + k for x = m·2^k, m in (√½, √2], the series to s¹⁹:
// within a few units in the last place of std::log2, and the same bits in every path (plain
// arithmetic, no contraction). Outside the normal positive doubles (0, subnormals, ∞, NaN), std::log2.
inline constexpr double kLog2Series[10] = {
    2 * 1.4426950408889634 / 1,  2 * 1.4426950408889634 / 3,  2 * 1.4426950408889634 / 5,
    2 * 1.4426950408889634 / 7,  2 * 1.4426950408889634 / 9,  2 * 1.4426950408889634 / 11,
    2 * 1.4426950408889634 / 13, 2 * 1.4426950408889634 / 15, 2 * 1.4426950408889634 / 17,
    2 * 1.4426950408889634 / 19};
inline constexpr double kSqrt2 = 1.4142135623730951;

inline double log2_series(double x) {
  if (!(x >= DBL_MIN && x <= DBL_MAX)) return std::log2(x);
  uint64_t b;
  std::memcpy(&b, &x, 8);
  uint64_t e = b >> 52;  // x > 0: no sign bit
  b = (b & 0x000fffffffffffffull) | 0x3ff0000000000000ull;
  double m;
  std::memcpy(&m, &b, 8);
  if (m > kSqrt2) m = m * 0.5, e += 1;
  const double k = double(int64_t(e)) - 1023.0;
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double p = kLog2Series[9];
  for (int i = 8; i >= 0; --i) p = p * s2 + kLog2Series[i];
  return k + s * p;
}

// Direction w's terms added to one lane's sums: the plain path's loop body, also the AVX2 path's
// for the directions beyond its last group of four.
inline void add_direction(const IrradiancePoly p[3], const AhdLobe& l, const double* w, bool with_log, double& se,
                          double& sl, double& lum) {
  const double cosine = std::max(0.0, w[0] * l.d[0] + w[1] * l.d[1] + w[2] * l.d[2]);
  for (int c = 0; c < 3; ++c) {
    const double ref = eval_irradiance(p[c], w);
    const double got = l.ca[c] + cosine * l.cd[c];
    const double d = got - ref;
    se += d * d;
    if (with_log) {
      const double dl = log2_series((1.0 + std::max(0.0, got)) / (1.0 + std::max(0.0, ref)));
      sl += dl * dl;
    }
    lum += kLumaWeights[c] * ref;
  }
}

// The four lanes' sums combined, in the one order every path uses.
inline HemisphereSums combine_lanes(const double se[4], const double sl[4], const double lum[4]) {
  HemisphereSums s;
  s.se = (se[0] + se[1]) + (se[2] + se[3]);
  s.sl = (sl[0] + sl[1]) + (sl[2] + sl[3]);
  s.lum = (lum[0] + lum[1]) + (lum[2] + lum[3]);
  return s;
}

}  // namespace ahd

// What the BC4/BC5 tests share (tests/unit and tests/accuracy bc4_bc5_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>
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

// The encoder's search as it was before its pairs were evaluated in batches (one pair at a time:
// palette, nearest entry per texel, squared error summed in texel order, kept if strictly better),
// written plainly: bc4_encode_block must write these bytes for every block and effort.
inline void reference_bc4_encode_block(const float texels[16], uint8_t out[8], int effort) {
  float v[16];
  float lo = 1.0f, hi = 0.0f;
  for (int i = 0; i < 16; ++i) {
    v[i] = std::clamp(std::isfinite(texels[i]) ? texels[i] : 0.0f, 0.0f, 1.0f);
    lo = std::min(lo, v[i]);
    hi = std::max(hi, v[i]);
  }
  auto write = [&](int r0, int r1, const uint8_t idx[16]) {
    out[0] = uint8_t(r0), out[1] = uint8_t(r1);
    uint64_t bits = 0;
    for (int i = 0; i < 16; ++i) bits |= uint64_t(idx[i] & 7) << (3 * i);
    for (int i = 0; i < 6; ++i) out[2 + i] = uint8_t(bits >> (8 * i));
  };
  const int qlo = int(std::floor(lo * 255.0f)), qhi = int(std::ceil(hi * 255.0f));
  if (qlo == qhi) {
    const uint8_t idx[16] = {};
    const int q = int(std::lround(v[0] * 255.0f));
    write(q, q, idx);
    return;
  }
  const int radius = effort <= 0 ? 0 : effort == 1 ? 2 : 4;
  float best = INFINITY;
  uint8_t best_idx[16] = {}, b0 = 0, b1 = 0;
  std::vector<bool> tried(65536);
  auto consider = [&](int r0, int r1) {
    if (r0 < 0 || r0 > 255 || r1 < 0 || r1 > 255 || tried[size_t(r0 * 256 + r1)]) return;
    tried[size_t(r0 * 256 + r1)] = true;
    float pal[8];
    bc4_palette(uint8_t(r0), uint8_t(r1), pal);
    uint8_t idx[16];
    float err = 0;
    for (int i = 0; i < 16; ++i) {
      float bd = std::fabs(v[i] - pal[0]);
      idx[i] = 0;
      for (int k = 1; k < 8; ++k) {
        const float d = std::fabs(v[i] - pal[k]);
        if (d < bd) bd = d, idx[i] = uint8_t(k);
      }
      err += bd * bd;
    }
    if (err < best) {
      best = err, b0 = uint8_t(r0), b1 = uint8_t(r1);
      std::copy(idx, idx + 16, best_idx);
    }
  };
  for (int a = -radius; a <= radius; ++a)
    for (int b = -radius; b <= radius; ++b)
      if (qhi + a > qlo + b) consider(qhi + a, qlo + b);
  float ilo = 1.0f, ihi = 0.0f;
  for (float x : v)
    if (x > 0.0f && x < 1.0f) ilo = std::min(ilo, x), ihi = std::max(ihi, x);
  if (ilo <= ihi) {
    const int plo = int(std::floor(ilo * 255.0f)), phi = int(std::ceil(ihi * 255.0f));
    for (int a = -radius; a <= radius; ++a)
      for (int b = -radius; b <= radius; ++b)
        if (plo + a <= phi + b) consider(plo + a, phi + b);
  }
  if (effort > 0) {
    for (int mode = 0; mode < 2; ++mode) {
      const bool eight = mode == 0;
      const int steps = eight ? 7 : 5;
      const float lo8 = (eight ? lo : ilo) * 255.0f, hi8 = (eight ? hi : ihi) * 255.0f;
      if (!(hi8 > lo8)) continue;
      for (int ta = 0; ta < steps; ++ta)
        for (int tb = ta + 1; tb <= steps; ++tb) {
          const float d = (hi8 - lo8) * steps / float(tb - ta);
          const float base = lo8 - d * ta / steps;
          const int b = int(std::lround(base)), top = int(std::lround(base + d));
          for (int da = -(effort > 1); da <= (effort > 1); ++da)
            for (int db = -(effort > 1); db <= (effort > 1); ++db) {
              if (eight && top + da > b + db) consider(top + da, b + db);
              if (!eight && b + db <= top + da) consider(b + db, top + da);
            }
        }
    }
    for (int iter = 0; iter < 2 + 2 * effort; ++iter) {
      const bool eight = b0 > b1;
      double s00 = 0, s01 = 0, s11 = 0, t0 = 0, t1 = 0;
      for (int i = 0; i < 16; ++i) {
        const int k = best_idx[i];
        if (!eight && k >= 6) continue;
        const double f = k == 0 ? 0.0 : k == 1 ? 1.0 : (k - 1) / (eight ? 7.0 : 5.0);
        const double x = v[i] * 255.0;
        s00 += (1 - f) * (1 - f), s01 += (1 - f) * f, s11 += f * f;
        t0 += (1 - f) * x, t1 += f * x;
      }
      const double det = s00 * s11 - s01 * s01;
      if (std::fabs(det) < 1e-9) break;
      const int e0 = int(std::lround((t0 * s11 - s01 * t1) / det)), e1 = int(std::lround((s00 * t1 - s01 * t0) / det));
      const uint8_t p0 = b0, p1 = b1;
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          const int r0 = std::clamp(e0 + a, 0, 255), r1 = std::clamp(e1 + b, 0, 255);
          if ((r0 > r1) == eight) consider(r0, r1);
        }
      if (p0 == b0 && p1 == b1) break;
    }
  }
  write(b0, b1, best_idx);
}

// Blocks of many kinds for the encoder's tests, `kind` in 0..11: uniform noise, ramps, two tight
// clusters, values on a random palette's entries, 0 / 1 ends with values between, constants, NaN /
// ±inf / out-of-range values, tiny ranges, a few neighbouring 8-bit steps, near-constant noise,
// 16-step ramps between two random values, halfway points between 8-bit steps.
inline void make_bc4_test_block(std::mt19937& rng, int kind, float v[16]) {
  std::uniform_real_distribution<float> u(0, 1);
  const float a = u(rng), s = u(rng) * (rng() % 2 ? 1.0f : 0.02f);
  switch (kind) {
    case 0: for (int i = 0; i < 16; ++i) v[i] = u(rng); break;
    case 1: for (int i = 0; i < 16; ++i) v[i] = a + s * (float(i % 4) / 3.0f + float(i / 4) / 5.0f - 0.5f); break;
    case 2: {
      const float b = u(rng);
      for (int i = 0; i < 16; ++i) v[i] = (rng() % 2 ? a : b) + 0.003f * (u(rng) - 0.5f);
    } break;
    case 3: {
      float pal[8];
      bc4_palette(uint8_t(rng() % 256), uint8_t(rng() % 256), pal);
      for (int i = 0; i < 16; ++i) v[i] = pal[rng() % 8];
    } break;
    case 4: for (int i = 0; i < 16; ++i) v[i] = rng() % 3 == 0 ? 0.0f : rng() % 2 ? 1.0f : a + s * (u(rng) - 0.5f); break;
    case 5: for (int i = 0; i < 16; ++i) v[i] = a; break;
    case 6:
      for (int i = 0; i < 16; ++i) {
        const int r = int(rng() % 8);
        v[i] = r == 0 ? NAN : r == 1 ? INFINITY : r == 2 ? -INFINITY : r == 3 ? -0.5f : r == 4 ? 2.0f : u(rng);
      }
      break;
    case 7: for (int i = 0; i < 16; ++i) v[i] = a + 1e-3f * u(rng); break;
    case 8: {
      const int q = int(rng() % 250);
      for (int i = 0; i < 16; ++i) v[i] = float(q + int(rng() % 6)) / 255.0f;
    } break;
    case 9: for (int i = 0; i < 16; ++i) v[i] = a + s * 0.1f * (u(rng) - 0.5f); break;
    case 10: {
      const float b = u(rng);
      for (int i = 0; i < 16; ++i) v[i] = a + (b - a) * float(i) / 15.0f;
    } break;
    default: {
      const int q = int(rng() % 256);
      for (int i = 0; i < 16; ++i) v[i] = (float(q) + 0.5f * float(rng() % 3)) / 255.0f;
    } break;
  }
}

}  // namespace ahd_fixture::bc4_fixture

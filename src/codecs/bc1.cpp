#include "codecs/bc1.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ahd {
namespace {

using Rgb = std::array<float, 3>;

Rgb expand565(uint16_t c) {
  return {float((c >> 11) & 31) / 31.0f, float((c >> 5) & 63) / 63.0f, float(c & 31) / 31.0f};
}

uint16_t pack565(const Rgb& c) {
  auto q = [](float v, int max) { return int(std::lround(std::clamp(v, 0.0f, 1.0f) * float(max))); };
  return uint16_t((q(c[0], 31) << 11) | (q(c[1], 63) << 5) | q(c[2], 31));
}

uint16_t read16(const uint8_t* p) { return uint16_t(p[0] | (p[1] << 8)); }

// Squared error of the 16 texels against the palette; writes the nearest index of each (the
// lower index on a tie). With three-colour blocks (c0 ≤ c1) only the first three entries are used.
float assign(const float tex[48], const float pal[4][3], int entries, uint8_t idx[16]) {
  float total = 0;
  for (int i = 0; i < 16; ++i) {
    float best = 1e30f;
    int bi = 0;
    for (int k = 0; k < entries; ++k) {
      float d = 0;
      for (int c = 0; c < 3; ++c) {
        const float e = tex[i * 3 + c] - pal[k][c];
        d += e * e;
      }
      if (d < best) best = d, bi = k;
    }
    idx[i] = uint8_t(bi);
    total += best;
  }
  return total;
}

struct Candidate {
  uint16_t c0 = 0, c1 = 0;
  uint8_t idx[16] = {};
  float err = 1e30f;
};

// Evaluates endpoints (a, b) as a four-colour block (swapped so that color0 > color1; equal
// endpoints give a one-colour block, every index 0).
Candidate evaluate(const float tex[48], uint16_t a, uint16_t b) {
  Candidate c;
  if (a < b) std::swap(a, b);
  c.c0 = a;
  c.c1 = b;
  float pal[4][3];
  bc1_palette(a, b, pal);
  c.err = assign(tex, pal, a == b ? 1 : 4, c.idx);
  return c;
}

// Least-squares endpoints for fixed indices: texel i ≈ w_i·A + (1 − w_i)·B with w = 1, 0, 2/3, 1/3
// for indices 0..3. Returns false when the indices use a single weight (no unique solution).
bool refit(const float tex[48], const uint8_t idx[16], Rgb& a, Rgb& b) {
  static constexpr float kW[4] = {1.0f, 0.0f, 2.0f / 3.0f, 1.0f / 3.0f};
  double aa = 0, ab = 0, bb = 0, ax[3] = {0, 0, 0}, bx[3] = {0, 0, 0};
  for (int i = 0; i < 16; ++i) {
    const double w = kW[idx[i]], v = 1.0 - w;
    aa += w * w;
    ab += w * v;
    bb += v * v;
    for (int c = 0; c < 3; ++c) {
      ax[c] += w * tex[i * 3 + c];
      bx[c] += v * tex[i * 3 + c];
    }
  }
  const double det = aa * bb - ab * ab;
  if (std::abs(det) < 1e-9) return false;
  for (int c = 0; c < 3; ++c) {
    a[size_t(c)] = std::clamp(float((ax[c] * bb - bx[c] * ab) / det), 0.0f, 1.0f);
    b[size_t(c)] = std::clamp(float((bx[c] * aa - ax[c] * ab) / det), 0.0f, 1.0f);
  }
  return true;
}

// One endpoint's channel moved by ±1 in its 565 field.
uint16_t nudge(uint16_t c, int channel, int step) {
  const int shift = channel == 0 ? 11 : channel == 1 ? 5 : 0, max = channel == 1 ? 63 : 31;
  const int v = (c >> shift) & max, n = std::clamp(v + step, 0, max);
  return uint16_t((c & ~(max << shift)) | (n << shift));
}

}  // namespace

void bc1_palette(uint16_t color0, uint16_t color1, float palette[4][3]) {
  const Rgb a = expand565(color0), b = expand565(color1);
  for (int c = 0; c < 3; ++c) {
    palette[0][c] = a[size_t(c)];
    palette[1][c] = b[size_t(c)];
    if (color0 > color1) {
      palette[2][c] = (2.0f * a[size_t(c)] + b[size_t(c)]) / 3.0f;
      palette[3][c] = (a[size_t(c)] + 2.0f * b[size_t(c)]) / 3.0f;
    } else {
      palette[2][c] = (a[size_t(c)] + b[size_t(c)]) / 2.0f;
      palette[3][c] = 0.0f;
    }
  }
}

void bc1_decode_block(const uint8_t block[8], float out[16 * 3]) {
  float pal[4][3];
  bc1_palette(read16(block), read16(block + 2), pal);
  const uint32_t bits = uint32_t(block[4]) | uint32_t(block[5]) << 8 | uint32_t(block[6]) << 16 | uint32_t(block[7]) << 24;
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) out[i * 3 + c] = pal[(bits >> (2 * i)) & 3][c];
}

void bc1_decode_block_unorm8(const uint8_t block[8], uint8_t out[16 * 3]) {
  const uint16_t c0 = read16(block), c1 = read16(block + 2);
  auto widen = [](uint16_t c, int ch) {
    if (ch == 0) return ((c >> 8) & 0xf8) | ((c >> 13) & 0x7);
    if (ch == 1) return ((c >> 3) & 0xfc) | ((c >> 9) & 0x3);
    return ((c << 3) & 0xf8) | ((c >> 2) & 0x7);
  };
  const uint32_t bits = uint32_t(block[4]) | uint32_t(block[5]) << 8 | uint32_t(block[6]) << 16 | uint32_t(block[7]) << 24;
  for (int i = 0; i < 16; ++i) {
    const int code = int((bits >> (2 * i)) & 3);
    for (int ch = 0; ch < 3; ++ch) {
      const int a = widen(c0, ch), b = widen(c1, ch);
      int v = 0;
      if (code == 0) v = a;
      else if (code == 1) v = b;
      else if (c0 > c1) v = code == 2 ? (2 * a + b) / 3 : (a + 2 * b) / 3;
      else v = code == 2 ? (a + b + 1) / 2 : 0;
      out[i * 3 + ch] = uint8_t(v);
    }
  }
}

void bc1_encode_block(const float texels[16 * 3], uint8_t out[8]) {
  float tex[48];
  for (int i = 0; i < 48; ++i) tex[i] = std::clamp(std::isfinite(texels[i]) ? texels[i] : 0.0f, 0.0f, 1.0f);

  // Principal axis of the colours (power iteration on the covariance).
  double mean[3] = {0, 0, 0};
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) mean[c] += tex[i * 3 + c] / 16.0;
  double cov[3][3] = {};
  for (int i = 0; i < 16; ++i)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) cov[r][c] += (tex[i * 3 + r] - mean[r]) * (tex[i * 3 + c] - mean[c]);
  double axis[3] = {1, 1, 1};
  for (int it = 0; it < 8; ++it) {
    double next[3] = {0, 0, 0};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) next[r] += cov[r][c] * axis[c];
    const double len = std::sqrt(next[0] * next[0] + next[1] * next[1] + next[2] * next[2]);
    if (len < 1e-12) break;
    for (int c = 0; c < 3; ++c) axis[c] = next[c] / len;
  }
  double tmin = 0, tmax = 0;
  for (int i = 0; i < 16; ++i) {
    double t = 0;
    for (int c = 0; c < 3; ++c) t += (tex[i * 3 + c] - mean[c]) * axis[c];
    tmin = std::min(tmin, t);
    tmax = std::max(tmax, t);
  }
  Rgb a{}, b{};
  for (int c = 0; c < 3; ++c) {
    a[size_t(c)] = float(mean[c] + tmax * axis[c]);
    b[size_t(c)] = float(mean[c] + tmin * axis[c]);
  }
  Candidate best = evaluate(tex, pack565(a), pack565(b));
  // Least-squares refits of the endpoints to the indices they produced.
  for (int it = 0; it < 3; ++it) {
    const Candidate from = best;
    if (from.c0 == from.c1 || !refit(tex, from.idx, a, b)) break;
    const Candidate c = evaluate(tex, pack565(a), pack565(b));
    if (c.err < best.err) best = c;
    else break;
  }
  // Greedy ±1 steps of each endpoint channel in its 565 field.
  for (bool improved = true; improved;) {
    improved = false;
    for (int e = 0; e < 2; ++e)
      for (int ch = 0; ch < 3; ++ch)
        for (int step : {-1, 1}) {
          const uint16_t n0 = e == 0 ? nudge(best.c0, ch, step) : best.c0;
          const uint16_t n1 = e == 1 ? nudge(best.c1, ch, step) : best.c1;
          const Candidate c = evaluate(tex, n0, n1);
          if (c.err < best.err) best = c, improved = true;
        }
  }
  out[0] = uint8_t(best.c0 & 0xff);
  out[1] = uint8_t(best.c0 >> 8);
  out[2] = uint8_t(best.c1 & 0xff);
  out[3] = uint8_t(best.c1 >> 8);
  uint32_t bits = 0;
  for (int i = 0; i < 16; ++i) bits |= uint32_t(best.idx[i]) << (2 * i);
  for (int k = 0; k < 4; ++k) out[4 + k] = uint8_t(bits >> (8 * k));
}

std::vector<uint8_t> bc1_encode_image(const ImageF& img) {
  const int bw = (img.width + 3) / 4, bh = (img.height + 3) / 4;
  std::vector<uint8_t> out(size_t(bw) * size_t(bh) * 8);
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      float tex[48];
      for (int i = 0; i < 16; ++i) {
        const int x = std::min(bx * 4 + i % 4, img.width - 1), y = std::min(by * 4 + i / 4, img.height - 1);
        for (int c = 0; c < 3; ++c) tex[i * 3 + c] = img.at(x, y)[c];
      }
      bc1_encode_block(tex, &out[(size_t(by) * size_t(bw) + size_t(bx)) * 8]);
    }
  return out;
}

ImageF bc1_decode_image(const uint8_t* blocks, int width, int height) {
  ImageF img(width, height, 3);
  const int bw = (width + 3) / 4;
  for (int by = 0; by * 4 < height; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      float tex[48];
      bc1_decode_block(blocks + (size_t(by) * size_t(bw) + size_t(bx)) * 8, tex);
      for (int i = 0; i < 16; ++i) {
        const int x = bx * 4 + i % 4, y = by * 4 + i / 4;
        if (x < width && y < height)
          for (int c = 0; c < 3; ++c) img.at(x, y)[c] = tex[i * 3 + c];
      }
    }
  return img;
}

}  // namespace ahd

// BC6H `fast`: a real-time UF16 encoder (endpoints fitted, not searched).
//
// Where real-time encoders get their speed (read in Basis Universal's transcoder encoder, facts
// only): one region and one mode for nearly every block, endpoints taken from the principal axis
// instead of searched, indices by projecting each texel on the endpoint segment instead of trying
// every palette entry, one or two least-squares passes, integer half bits throughout. Our design
// keeps that shape and adds what our guarantees and metric need:
//  * Half-bit domain (as bc6h_encoder.cpp): BC6H interpolates linearly in a 16-bit domain that
//    maps to half bits by ×31/64, and half bits are piecewise linear in log2, so lines fitted on
//    half bits are lines in the metric. Each texel-channel is weighted by (x/(1+x))², the slope of
//    log2(1+x) per half step (floored at x = 0.25), so the fit minimises the judged error.
//  * The most precise one-region mode whose endpoint delta fits (14: 16 bits ±8 → 13: 12 bits ±128
//    → 12: 11 bits ±256 → 11: 10 bits absolute): smooth blocks keep 16-, 12- or 11-bit
//    endpoints instead of 10, which is where most of a lightmap's error would be.
//  * No specks by construction: every endpoint is quantised so that it decodes at most one half
//    step above its channel's brightest input (rounded down when nearest rounding would exceed
//    it), and every palette entry lies between the endpoints, so no texel can speckle.
//  * Solid blocks are mode 14 with exact endpoints (a half-bit value is always representable).
// This file is the one-block path (plain C++ and SSE2 over the 16 texels); images go through
// fit_blocks_fast (`fast`, and `default` for its incumbents), which fits sixteen blocks per batch
// on AVX-512 CPUs and eight on AVX2 ones (bc6h_fast_lanes.inc, the same operations lane by lane).
// In `fast`, blocks whose one-region error is high then get a two-region candidate
// (bc6h_fast_two_region.cpp), kept when it is better. Bytes depend only on the block.
#include "codecs/bc6h/bc6h_fast.h"

#include <Imath/half.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/cpu.h"

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace ahd::bc6h {

// ---- half conversion -------------------------------------------------------------------------

void floats_to_half_portable(const float* in, uint16_t* out, int n) {
  for (int i = 0; i < n; ++i) out[i] = Imath::half(in[i]).bits();
}

void floats_to_half(const float* in, uint16_t* out, int n) {
  if (cpu::has(cpu::kF16c)) return floats_to_half_f16c(in, out, n);
  floats_to_half_portable(in, out, n);
}

// ---- the encoder -----------------------------------------------------------------------------

namespace {

// Sum of 16 floats in four lanes (t mod 4), a fixed order the compiler can vectorise.
inline float sum16(const float v[16]) {
  alignas(16) float l[4] = {0, 0, 0, 0};
#ifdef __SSE2__
  if (cpu::has(cpu::kSse2)) {
    __m128 acc = _mm_setzero_ps();
    for (int t = 0; t < 16; t += 4) acc = _mm_add_ps(acc, _mm_loadu_ps(v + t));
    _mm_store_ps(l, acc);
    return (l[0] + l[1]) + (l[2] + l[3]);
  }
#endif
  for (int t = 0; t < 16; t += 4)
    for (int i = 0; i < 4; ++i) l[i] += v[t + i];
  return (l[0] + l[1]) + (l[2] + l[3]);
}

// Least-squares passes after the axis fit (each kept only if it lowers the error).
constexpr int kPasses = 2;

constexpr int kW4[16] = {0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64};

// Palette index nearest to a position p = 128·t on the segment (t in [0, 1]).
struct NearestIndex {
  uint8_t idx[129];
  constexpr NearestIndex() : idx{} {
    for (int p = 0; p <= 128; ++p) {
      int best = 0;
      for (int k = 1; k < 16; ++k) {
        const int d = 2 * kW4[k] - p, db = 2 * kW4[best] - p;
        if ((d < 0 ? -d : d) < (db < 0 ? -db : db)) best = k;
      }
      idx[p] = uint8_t(best);
    }
  }
};
constexpr NearestIndex kNearest;

// One-region modes by precision: mode number (0-based), endpoint bits, delta bits, mode code.
struct OneRegionMode {
  int mode, epb, delta, code;
};
constexpr OneRegionMode kModes[4] = {{13, 16, 4, 0x0f}, {12, 12, 8, 0x0b}, {11, 11, 9, 0x07}, {10, 10, 10, 0x03}};

inline int unquantize_u(int e, int bits) {
  if (bits >= 15) return e;
  if (e == 0) return 0;
  if (e == (1 << bits) - 1) return 0xFFFF;
  return ((e << 16) + 0x8000) >> bits;
}
inline int decode_h(int c) { return (c * 31) >> 6; }

// The endpoint component (bits wide) whose decoded half bits are nearest `target` (half bits,
// float) without exceeding `cap`.
inline int quantize_endpoint(float target, int bits, int cap) {
  const int maxv = (1 << bits) - 1;
  const float c = target * (64.0f / 31.0f);
  int e = int(c * float(1 << bits) * (1.0f / 65536.0f));
  e = std::clamp(e, 0, maxv);
  // Candidates e and e+1 bracket the target; keep the nearer (ties to the lower one).
  if (e < maxv && std::fabs(float(decode_h(unquantize_u(e + 1, bits))) - target) <
                      std::fabs(float(decode_h(unquantize_u(e, bits))) - target))
    ++e;
  while (e > 0 && decode_h(unquantize_u(e, bits)) > cap) --e;
  return e;
}

struct Fit {
  float H[3][16];  // half bits as floats
  float W[3][16];  // metric weight per texel-channel (0 for padding)
  int cap[3];
  float lo[3], hi[3];  // per-channel range of the valid texels
};

struct Endpoints {
  int m = 3;  // index into kModes
  int e[2][3];
};

void store(const Endpoints& ep, const uint8_t idx[16], float err, OneRegionFit* out) {
  out->mode = kModes[ep.m].mode;
  std::memcpy(out->e, ep.e, sizeof out->e);
  std::memcpy(out->idx, idx, 16);
  out->err = err;
}

// Palette (decoded half bits) of two quantised endpoints, per channel.
inline void palette(const Endpoints& ep, float P[3][16]) {
  const int bits = kModes[ep.m].epb;
  for (int c = 0; c < 3; ++c) {
    const int a = unquantize_u(ep.e[0][c], bits), b = unquantize_u(ep.e[1][c], bits);
    for (int k = 0; k < 16; ++k) P[c][k] = float(decode_h((a * (64 - kW4[k]) + b * kW4[k] + 32) >> 6));
  }
}

// Each texel's position on the palette's segment, 0..128, by weighted projection.
void project(const Fit& f, const float P[3][16], int pos[16]) {
  const float d0 = P[0][15] - P[0][0], d1 = P[1][15] - P[1][0], d2 = P[2][15] - P[2][0];
  for (int t = 0; t < 16; ++t) {
    const float w0 = f.W[0][t], w1 = f.W[1][t], w2 = f.W[2][t];
    const float num = w0 * d0 * (f.H[0][t] - P[0][0]) + w1 * d1 * (f.H[1][t] - P[1][0]) + w2 * d2 * (f.H[2][t] - P[2][0]);
    const float den = w0 * d0 * d0 + w1 * d1 * d1 + w2 * d2 * d2;
    const float p = 128.0f * num / (den > 0 ? den : 1.0f);
    pos[t] = int(std::min(std::max(p, 0.0f), 128.0f) + 0.5f);
  }
}

#ifdef __SSE2__
// palette() and project() four lanes at a time: the same operations in the same order. (GCC
// keeps the plain loops scalar: it will not turn their float selects into blends while
// comparisons may trap.) Integers stay exact in floats here: every intermediate is below 2^23.
void palette_sse2(const Endpoints& ep, float P[3][16]) {
  const int bits = kModes[ep.m].epb;
  const __m128 inv64 = _mm_set1_ps(1.0f / 64.0f), k31 = _mm_set1_ps(31.0f), k32 = _mm_set1_ps(32.0f);
  for (int c = 0; c < 3; ++c) {
    const __m128 a = _mm_set1_ps(float(unquantize_u(ep.e[0][c], bits)));
    const __m128 b = _mm_set1_ps(float(unquantize_u(ep.e[1][c], bits)));
    for (int v = 0; v < 4; ++v) {
      const __m128 w = _mm_setr_ps(float(kW4[4 * v]), float(kW4[4 * v + 1]), float(kW4[4 * v + 2]), float(kW4[4 * v + 3]));
      const __m128 sum = _mm_add_ps(_mm_add_ps(_mm_mul_ps(a, _mm_sub_ps(_mm_set1_ps(64.0f), w)), _mm_mul_ps(b, w)), k32);
      const __m128 cv = _mm_cvtepi32_ps(_mm_cvttps_epi32(_mm_mul_ps(sum, inv64)));  // >> 6 (non-negative)
      _mm_storeu_ps(&P[c][4 * v], _mm_cvtepi32_ps(_mm_cvttps_epi32(_mm_mul_ps(_mm_mul_ps(cv, k31), inv64))));
    }
  }
}

void project_sse2(const Fit& f, const float P[3][16], int pos[16]) {
  const __m128 d0 = _mm_set1_ps(P[0][15] - P[0][0]), d1 = _mm_set1_ps(P[1][15] - P[1][0]),
               d2 = _mm_set1_ps(P[2][15] - P[2][0]);
  const __m128 p0 = _mm_set1_ps(P[0][0]), p1 = _mm_set1_ps(P[1][0]), p2 = _mm_set1_ps(P[2][0]);
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), k128 = _mm_set1_ps(128.0f), half = _mm_set1_ps(0.5f);
  for (int t = 0; t < 16; t += 4) {
    const __m128 wd0 = _mm_mul_ps(_mm_loadu_ps(&f.W[0][t]), d0), wd1 = _mm_mul_ps(_mm_loadu_ps(&f.W[1][t]), d1),
                 wd2 = _mm_mul_ps(_mm_loadu_ps(&f.W[2][t]), d2);
    const __m128 num = _mm_add_ps(_mm_add_ps(_mm_mul_ps(wd0, _mm_sub_ps(_mm_loadu_ps(&f.H[0][t]), p0)),
                                             _mm_mul_ps(wd1, _mm_sub_ps(_mm_loadu_ps(&f.H[1][t]), p1))),
                                  _mm_mul_ps(wd2, _mm_sub_ps(_mm_loadu_ps(&f.H[2][t]), p2)));
    const __m128 den = _mm_add_ps(_mm_add_ps(_mm_mul_ps(wd0, d0), _mm_mul_ps(wd1, d1)), _mm_mul_ps(wd2, d2));
    const __m128 pos_den = _mm_cmpgt_ps(den, zero);
    const __m128 safe = _mm_or_ps(_mm_and_ps(pos_den, den), _mm_andnot_ps(pos_den, one));
    const __m128 p = _mm_min_ps(_mm_max_ps(_mm_div_ps(_mm_mul_ps(k128, num), safe), zero), k128);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(&pos[t]), _mm_cvttps_epi32(_mm_add_ps(p, half)));
  }
}
#endif

#ifdef __SSE2__
// The neighbour check of assign() for four texels at a time (palette entries gathered into
// lanes); the same operations in the same order, the total summed texel by texel as there.
float pick_sse2(const Fit& f, const float P[3][16], const int pos[16], uint8_t idx[16]) {
  float total = 0;
  for (int t = 0; t < 16; t += 4) {
    int k[4], km[4], kp[4];
    for (int l = 0; l < 4; ++l) {
      k[l] = kNearest.idx[pos[t + l]];
      km[l] = k[l] - (k[l] > 0), kp[l] = k[l] + (k[l] < 15);
    }
    const __m128 w0 = _mm_loadu_ps(&f.W[0][t]), w1 = _mm_loadu_ps(&f.W[1][t]), w2 = _mm_loadu_ps(&f.W[2][t]);
    const __m128 h0 = _mm_loadu_ps(&f.H[0][t]), h1 = _mm_loadu_ps(&f.H[1][t]), h2 = _mm_loadu_ps(&f.H[2][t]);
    auto err = [&](const int j[4]) {
      const __m128 e0 = _mm_sub_ps(_mm_setr_ps(P[0][j[0]], P[0][j[1]], P[0][j[2]], P[0][j[3]]), h0);
      const __m128 e1 = _mm_sub_ps(_mm_setr_ps(P[1][j[0]], P[1][j[1]], P[1][j[2]], P[1][j[3]]), h1);
      const __m128 e2 = _mm_sub_ps(_mm_setr_ps(P[2][j[0]], P[2][j[1]], P[2][j[2]], P[2][j[3]]), h2);
      return _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(w0, e0), e0), _mm_mul_ps(_mm_mul_ps(w1, e1), e1)),
                        _mm_mul_ps(_mm_mul_ps(w2, e2), e2));
    };
    alignas(16) float ek[4], em[4], ep[4];
    _mm_store_ps(ek, err(k));
    _mm_store_ps(em, err(km));
    _mm_store_ps(ep, err(kp));
    for (int l = 0; l < 4; ++l) {
      int kb = em[l] < ek[l] ? km[l] : k[l];
      float best = em[l] < ek[l] ? em[l] : ek[l];
      kb = ep[l] < best ? kp[l] : kb;
      best = ep[l] < best ? ep[l] : best;
      idx[t + l] = uint8_t(kb);
      total += best;
    }
  }
  return total;
}
#endif

// Indices by weighted projection on the palette's segment, then the better neighbour; returns
// the weighted squared error in half steps. Every palette entry lies within the block's range
// (the endpoints do), so any index is allowed.
float assign(const Fit& f, const Endpoints& ep, uint8_t idx[16]) {
  float P[3][16];
  int pos[16];
#ifdef __SSE2__
  if (cpu::has(cpu::kSse2)) {
    palette_sse2(ep, P);
    project_sse2(f, P, pos);
    return pick_sse2(f, P, pos, idx);
  }
#endif
  palette(ep, P);
  project(f, P, pos);
  float total = 0;
  for (int t = 0; t < 16; ++t) {
    const float w0 = f.W[0][t], w1 = f.W[1][t], w2 = f.W[2][t];
    const float h0 = f.H[0][t], h1 = f.H[1][t], h2 = f.H[2][t];
    auto err = [&](int j) {
      const float e0 = P[0][j] - h0, e1 = P[1][j] - h1, e2 = P[2][j] - h2;
      return w0 * e0 * e0 + w1 * e1 * e1 + w2 * e2 * e2;
    };
    // Both neighbours, branch-free (at the ends the "neighbour" is k itself and never wins).
    const int k = kNearest.idx[pos[t]], km = k - (k > 0), kp = k + (k < 15);
    const float ek = err(k), em = err(km), ep = err(kp);
    int kb = em < ek ? km : k;
    float best = em < ek ? em : ek;
    kb = ep < best ? kp : kb;
    best = ep < best ? ep : best;
    idx[t] = uint8_t(kb);
    total += best;
  }
  return total;
}

// Quantises endpoint targets (half bits) in the most precise one-region mode whose delta fits,
// never decoding above the channel's cap. A mode whose delta cannot fit by the targets' spread
// (quantising moves an endpoint by under one step each) is skipped before quantising.
Endpoints quantize(const Fit& f, const float a[3], const float b[3]) {
  float spread = 0;  // in 16-bit interpolation units
  for (int c = 0; c < 3; ++c) spread = std::max(spread, std::fabs(b[c] - a[c]) * (64.0f / 31.0f));
  Endpoints ep;
  for (int m = 0; m < 3; ++m) {
    const OneRegionMode& md = kModes[m];
    const int lim = (1 << (md.delta - 1)) - 1;  // symmetric, so the endpoints can be swapped
    if (spread > float((lim + 2) << (16 - md.epb))) continue;
    bool fits = true;
    for (int c = 0; c < 3 && fits; ++c) {
      ep.e[0][c] = quantize_endpoint(a[c], md.epb, f.cap[c]);
      ep.e[1][c] = quantize_endpoint(b[c], md.epb, f.cap[c]);
      const int d = ep.e[1][c] - ep.e[0][c];
      fits = d >= -lim && d <= lim;
    }
    if (fits) {
      ep.m = m;
      return ep;
    }
  }
  ep.m = 3;  // 10-bit absolute endpoints: always representable
  for (int c = 0; c < 3; ++c) {
    ep.e[0][c] = quantize_endpoint(a[c], 10, f.cap[c]);
    ep.e[1][c] = quantize_endpoint(b[c], 10, f.cap[c]);
  }
  return ep;
}

// Least squares for the endpoints given the indices (per channel, weighted), in half bits.
bool refit(const Fit& f, const uint8_t idx[16], float a[3], float b[3]) {
  float g[16];
  for (int t = 0; t < 16; ++t) g[t] = float(kW4[idx[t]]) * (1.0f / 64.0f);
  for (int c = 0; c < 3; ++c) {
    // Four partial sums (lanes t mod 4): the same sums with SSE2 or without.
    alignas(16) float p00[4] = {}, p01[4] = {}, p11[4] = {}, q0[4] = {}, q1[4] = {};
#ifdef __SSE2__
    if (cpu::has(cpu::kSse2)) {
      const __m128 one = _mm_set1_ps(1.0f);
      __m128 s00 = _mm_setzero_ps(), s01 = s00, s11 = s00, r0 = s00, r1 = s00;
      for (int t = 0; t < 16; t += 4) {
        const __m128 gg = _mm_loadu_ps(g + t), w = _mm_loadu_ps(&f.W[c][t]), hh = _mm_loadu_ps(&f.H[c][t]);
        const __m128 om = _mm_sub_ps(one, gg), wa = _mm_mul_ps(w, om), wb = _mm_mul_ps(w, gg);
        s00 = _mm_add_ps(s00, _mm_mul_ps(wa, om)), s01 = _mm_add_ps(s01, _mm_mul_ps(wa, gg));
        s11 = _mm_add_ps(s11, _mm_mul_ps(wb, gg));
        r0 = _mm_add_ps(r0, _mm_mul_ps(wa, hh)), r1 = _mm_add_ps(r1, _mm_mul_ps(wb, hh));
      }
      _mm_store_ps(p00, s00), _mm_store_ps(p01, s01), _mm_store_ps(p11, s11), _mm_store_ps(q0, r0), _mm_store_ps(q1, r1);
    } else
#endif
      for (int t = 0; t < 16; t += 4)
        for (int l = 0; l < 4; ++l) {
          const float gg = g[t + l], w = f.W[c][t + l], hh = f.H[c][t + l], wa = w * (1 - gg), wb = w * gg;
          p00[l] += wa * (1 - gg), p01[l] += wa * gg, p11[l] += wb * gg;
          q0[l] += wa * hh, q1[l] += wb * hh;
        }
    const float s00 = (p00[0] + p00[1]) + (p00[2] + p00[3]), s01 = (p01[0] + p01[1]) + (p01[2] + p01[3]),
                s11 = (p11[0] + p11[1]) + (p11[2] + p11[3]), t0 = (q0[0] + q0[1]) + (q0[2] + q0[3]),
                t1 = (q1[0] + q1[1]) + (q1[2] + q1[3]);
    if (!solve_endpoints_held_cap(s00, s01, s11, t0, t1, float(f.cap[c]), &a[c], &b[c])) return false;
  }
  return true;
}

// Writes a one-region block: 5 mode bits, the low 10 bits of each base endpoint, then per channel
// the delta (or second endpoint) followed by the base's high bits from the highest down, then the
// indices (texel 0 without its top bit). This is the spec's layout of modes 11–14. In every one of
// them a channel's second field (delta + high bits) is 10 bits, so the header is 65 bits with
// every field at a fixed place: 64-bit ORs, no 128-bit shifts.
// The low n ≤ 6 bits of v in reverse order is kReverse6[v] >> (6 − n).
struct Reverse6 {
  uint8_t r[64];
  constexpr Reverse6() : r{} {
    for (int v = 0; v < 64; ++v)
      for (int b = 0; b < 6; ++b) r[v] |= uint8_t(((v >> b) & 1) << (5 - b));
  }
};
constexpr Reverse6 kReverse6;

// Sixteen values below 16 (bytes) as the nibbles of one 64-bit word, value t at bits 4t..4t+3.
inline uint64_t nibbles(const uint8_t v[16]) {
  uint64_t a, b;
  std::memcpy(&a, v, 8), std::memcpy(&b, v + 8, 8);
  if constexpr (std::endian::native != std::endian::little) {
    uint64_t r = 0;
    for (int t = 0; t < 16; ++t) r |= uint64_t(v[t]) << (4 * t);
    return r;
  }
  a = (a | (a >> 4)) & 0x00FF00FF00FF00FFull, b = (b | (b >> 4)) & 0x00FF00FF00FF00FFull;
  a = (a | (a >> 8)) & 0x0000FFFF0000FFFFull, b = (b | (b >> 8)) & 0x0000FFFF0000FFFFull;
  a = (a | (a >> 16)) & 0xFFFFFFFFull, b = (b | (b >> 16)) & 0xFFFFFFFFull;
  return a | b << 32;
}

// idx: texel t's index at bits 4t (texel 0's below 8).
void pack(const Endpoints& ep, uint64_t idx, uint8_t out[16]) {
  const OneRegionMode& md = kModes[ep.m];
  uint64_t lo = uint64_t(md.code);
  for (int c = 0; c < 3; ++c) lo |= uint64_t(ep.e[0][c] & 0x3FF) << (5 + 10 * c);
  uint64_t second[3];
  const int high = md.epb - 10;  // the base's bits above 10, written from the highest down
  for (int c = 0; c < 3; ++c) {
    const int d = (ep.e[1][c] - (md.delta < md.epb ? ep.e[0][c] : 0)) & ((1 << md.delta) - 1);
    second[c] = unsigned(d) | uint64_t(kReverse6.r[ep.e[0][c] >> 10] >> (6 - high)) << md.delta;
  }
  lo |= second[0] << 35 | second[1] << 45 | second[2] << 55;  // bit 9 of the blue field is bit 64
  // The indices fill the high 64 bits from bit 1 (texel 0's 3 bits).
  const uint64_t hi = (second[2] >> 9) | (idx & 0xF) << 1 | (idx & ~uint64_t(0xF));
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(out, &lo, 8), std::memcpy(out + 8, &hi, 8);
  } else {
    for (int i = 0; i < 8; ++i) out[i] = uint8_t(lo >> (8 * i)), out[8 + i] = uint8_t(hi >> (8 * i));
  }
}

}  // namespace

void fit_one_region_fast(const uint16_t h[48], const float x[48], const uint8_t valid[16], OneRegionFit* out) {
  Fit f;
  // Channel planes. Padding texels take the values of the first real one, so that plain minima
  // and maxima over all 16 are those of the real texels; their weight is 0.
  int first = 0;
  while (first < 15 && !valid[first]) ++first;
  float vmask[16];
  for (int t = 0; t < 16; ++t) {
    const int s = valid[t] ? t : first;
    vmask[t] = valid[t] ? 1.0f : 0.0f;
    for (int c = 0; c < 3; ++c) f.H[c][t] = float(h[s * 3 + c]), f.W[c][t] = x[s * 3 + c];
  }
  for (int c = 0; c < 3; ++c) {
    float lo = f.H[c][0], hi = f.H[c][0];
    for (int t = 0; t < 16; ++t) {  // vectorised
      const float xv = std::max(f.W[c][t], 0.25f), slope = xv / (1.0f + xv);
      f.W[c][t] = slope * slope * vmask[t];
      lo = std::min(lo, f.H[c][t]), hi = std::max(hi, f.H[c][t]);
    }
    f.lo[c] = lo, f.hi[c] = hi, f.cap[c] = int(hi) + 1;
  }
  float tw[16];
  for (int t = 0; t < 16; ++t) tw[t] = (f.W[0][t] + f.W[1][t] + f.W[2][t]) * (1.0f / 3.0f);
  const float wsum = sum16(tw);

  uint8_t idx[16] = {};
  if (f.lo[0] == f.hi[0] && f.lo[1] == f.hi[1] && f.lo[2] == f.hi[2]) {
    // Solid: mode 14 with both endpoints the exact 16-bit value (ceil(64h/31) decodes to h).
    Endpoints ep;
    ep.m = 0;
    for (int c = 0; c < 3; ++c) ep.e[0][c] = ep.e[1][c] = (int(f.hi[c]) * 64 + 30) / 31;
    store(ep, idx, 0.0f, out);
    return;
  }

  // Principal axis of the weighted texels (power iteration from the covariance's diagonal).
  float mean[3], tmp[6][16];
  for (int c = 0; c < 3; ++c) {
    for (int t = 0; t < 16; ++t) tmp[c][t] = tw[t] * f.H[c][t];
    mean[c] = sum16(tmp[c]) / wsum;
  }
  for (int t = 0; t < 16; ++t) {
    const float d0 = f.H[0][t] - mean[0], d1 = f.H[1][t] - mean[1], d2 = f.H[2][t] - mean[2], w = tw[t];
    tmp[0][t] = w * d0 * d0, tmp[1][t] = w * d1 * d1, tmp[2][t] = w * d2 * d2;
    tmp[3][t] = w * d0 * d1, tmp[4][t] = w * d0 * d2, tmp[5][t] = w * d1 * d2;
  }
  float cov[6];  // xx yy zz xy xz yz
  for (int i = 0; i < 6; ++i) cov[i] = sum16(tmp[i]);
  float ax[3], len2;
  principal_axis(cov, ax, &len2);
  float tmin = 1e30f, tmax = -1e30f;
  for (int t = 0; t < 16; ++t) {
    if (!valid[t]) continue;
    const float p = (f.H[0][t] - mean[0]) * ax[0] + (f.H[1][t] - mean[1]) * ax[1] + (f.H[2][t] - mean[2]) * ax[2];
    tmin = std::min(tmin, p), tmax = std::max(tmax, p);
  }
  float a[3], b[3];
  for (int c = 0; c < 3; ++c) {
    a[c] = std::clamp(mean[c] + tmin / len2 * ax[c], f.lo[c], f.hi[c]);
    b[c] = std::clamp(mean[c] + tmax / len2 * ax[c], f.lo[c], f.hi[c]);
  }

  Endpoints best = quantize(f, a, b);
  float best_err = assign(f, best, idx);
  for (int pass = 0; pass < kPasses && best_err > 0; ++pass) {
    if (!refit(f, idx, a, b)) break;
    const Endpoints ep = quantize(f, a, b);
    uint8_t trial[16];
    const float err = assign(f, ep, trial);
    if (!(err < best_err)) break;
    best = ep, best_err = err;
    std::memcpy(idx, trial, 16);
  }
  store(best, idx, best_err, out);
}

void encode_block_fast(const uint16_t h[48], const float x[48], const uint8_t valid[16], uint8_t out[16]) {
  OneRegionFit fit;
  fit_one_region_fast(h, x, valid, &fit);
  pack_one_region(fit, out);
  improve_with_two_regions(h, x, valid, fit.err, out);
}

bool copy_block_in_range(const float* p, size_t stride, float rgb[48]) {
#ifdef __SSE2__
  const __m128 zero = _mm_setzero_ps(), top = _mm_set1_ps(65504.0f);
  __m128 ok = _mm_castsi128_ps(_mm_set1_epi32(-1));
  for (int y = 0; y < 4; ++y)
    for (int i = 0; i < 3; ++i) {
      const __m128 v = _mm_loadu_ps(p + y * stride + 4 * i);  // ordered compares: NaN fails
      ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmple_ps(v, top)));
      _mm_storeu_ps(rgb + 12 * y + 4 * i, v);
    }
  return _mm_movemask_ps(ok) == 0xF;
#else
  bool ok = true;
  for (int y = 0; y < 4; ++y)
    for (int i = 0; i < 12; ++i) {
      const float v = p[y * stride + i];
      ok &= v >= 0.0f && v <= 65504.0f;
      rgb[12 * y + i] = v;
    }
  return ok;
#endif
}

// One batch of `lanes` blocks from block i on (a partial batch repeats block i), through fit.
template <int lanes, class Fit>
static void fit_batch(const uint16_t* h, const float* x, const uint8_t* valid, int n, int i, OneRegionFit* fits,
                      Fit fit) {
  const uint16_t* hp[lanes];
  const float* xp[lanes];
  const uint8_t* vp[lanes];
  OneRegionFit* op[lanes];
  for (int l = 0; l < lanes; ++l) {
    const int b = i + l < n ? i + l : i;
    hp[l] = h + 48 * b, xp[l] = x + 48 * b, vp[l] = valid + 16 * b;
    op[l] = i + l < n ? fits + i + l : nullptr;
  }
  fit(hp, xp, vp, op);
}

void fit_blocks_fast(const uint16_t* h, const float* x, const uint8_t* valid, int n, OneRegionFit* fits) {
  int i = 0;
  if (cpu::has(cpu::kAvx512)) {
    // Up to kMaxBatches batches of sixteen at a time (their second passes gathered); a last
    // batch of at most eight blocks takes the AVX2 path (half the lanes' work; same fits).
    for (; n - i > 8; i += 16 * kMaxBatches) {
      const int batches = std::min(kMaxBatches, (n - i + 15) / 16);
      fit_batch<16 * kMaxBatches>(h, x, valid, n, i, fits, [batches](auto hp, auto xp, auto vp, auto op) {
        fit_blocks_fast_x16n(batches, hp, xp, vp, op);
      });
    }
  }
  if (cpu::has(cpu::kAvx2)) {
    for (; i < n; i += 8) fit_batch<8>(h, x, valid, n, i, fits, fit_blocks_fast_x8);
    return;
  }
  for (; i < n; ++i) fit_one_region_fast(h + 48 * i, x + 48 * i, valid + 16 * i, fits + i);
}

void encode_blocks_fast(const uint16_t* h, const float* x, const uint8_t* valid, int n, uint8_t* out) {
  for (int i = 0; i < n; i += 16 * kMaxBatches) {  // kMaxBatches AVX-512 batches of fits on the stack at a time
    const int m = std::min(16 * kMaxBatches, n - i);
    float err[16 * kMaxBatches];
    int j = 0;
    if (cpu::has(cpu::kAvx512) && m > 8) {
      // The AVX-512 batches pack in their lanes (the blocks pack_one_region writes); as in
      // fit_blocks_fast, at most eight blocks take the path below instead.
      const int full = m;
      const uint16_t* hp[16 * kMaxBatches];
      const float* xp[16 * kMaxBatches];
      const uint8_t* vp[16 * kMaxBatches];
      uint8_t* bp[16 * kMaxBatches];
      float* ep[16 * kMaxBatches];
      for (int l = 0; l < 16 * kMaxBatches; ++l) {
        const int b = i + (l < full ? l : 0);  // padding repeats the first block
        hp[l] = h + 48 * b, xp[l] = x + 48 * b, vp[l] = valid + 16 * b;
        bp[l] = l < full ? out + 16 * (i + l) : nullptr, ep[l] = err + l;
      }
      encode_blocks_fast_x16n((full + 15) / 16, hp, xp, vp, bp, ep);
      j = full;
    }
    if (j < m) {
      OneRegionFit fits[16 * kMaxBatches];
      fit_blocks_fast(h + 48 * (i + j), x + 48 * (i + j), valid + 16 * (i + j), m - j, fits);
      for (int k = j; k < m; ++k) pack_one_region(fits[k - j], out + 16 * (i + k)), err[k] = fits[k - j].err;
    }
    for (int k = 0; k < m; ++k) {
      const int b = i + k;
      improve_with_two_regions(h + 48 * b, x + 48 * b, valid + 16 * b, err[k], out + 16 * b);
    }
  }
}

void pack_one_region(OneRegionFit fit, uint8_t out[16]) { pack_one_region(fit.mode, fit.e, nibbles(fit.idx), out); }

void pack_one_region(int mode, const int e[2][3], uint64_t idx, uint8_t out[16]) {
  Endpoints ep;
  ep.m = 13 - mode;  // kModes lists modes 13, 12, 11, 10
  std::memcpy(ep.e, e, sizeof ep.e);
  // Texel 0's index is stored without its top bit: mirror the block when it is set (the palette
  // is symmetric, and quantize() keeps deltas inside the symmetric part of their range).
  if ((idx & 0xF) >= 8) {
    for (int c = 0; c < 3; ++c) std::swap(ep.e[0][c], ep.e[1][c]);
    idx = ~idx;  // 15 − k in every nibble
  }
  pack(ep, idx, out);
}

}  // namespace ahd::bc6h

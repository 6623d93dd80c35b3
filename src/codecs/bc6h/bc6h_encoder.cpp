// BC6H encoder.
//
// Working domain: BC6H interpolates endpoints linearly in a 16-bit domain c that the decoder maps
// to half-float bits by a fixed scale (c·31/64 unsigned, c·31/32 signed). Half-float bits are
// piecewise linear in log2(value), so the codec is linear in a log-like space. We fit endpoints
// there (principal axis, then weighted least squares on the indices) and measure the error
// exactly: the decoder's half bits against the input's half bits, weighted per texel and channel
// by (x/(1+x))², the slope of log2(1+x) per half-float step — the metric HDR lightmaps are judged
// by (PEERS.md), large values relative, values below 1 closer to absolute.
//
// Quality levels choose how many candidates are tried:
//   fast    UF16: the real-time path of bc6h_fast.cpp (one region, endpoints from the principal
//           axis in the most precise mode whose delta fits; a two-region candidate only for
//           blocks whose one-region error is high). SF16: one region +
//           the best two-region partition, the 2 most precise modes whose deltas fit, no refinement
//   default UF16: the real-time fit as the incumbent (eight blocks per AVX2 batch in images, as
//           fast); where that fit is poor, its indices re-picked
//           in the judged metric and its endpoints polished, and 2 partitions only for blocks
//           that are not noise along one line (encode_block_default). SF16: one region + 2 best
//           partitions, 2 refinement passes on the best candidate of each
//   high    one region + 6 partitions, 3 modes each, 4 refinement passes on the 2 best
//   max     one region + all 32 partitions, every mode, 6 passes, ±1 endpoint perturbation,
//           then the 4 best candidates polished on the quantised lattice (search_max)
// No specks: no texel may decode above its channel's brightest input in the block (or, signed,
// below the darkest) by more than one half-float step. Every candidate is evaluated with that
// range enforced (palette entries outside it are never chosen), and one candidate that lies
// inside it by construction is always in the running, so the bound holds for every block. One
// search does it: a first unconstrained search with a re-search of overshooting blocks cost up
// to 2× on noisy images for a log-RMSE difference below 3 %.
#include <Imath/half.h>

#include <bit>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "codecs/bc6h/bc6h_codec.h"
#include "codecs/bc6h/bc6h_fast.h"
#include "codecs/bc6h/bc6h_search_avx2.h"
#include "codecs/bc6h/bc6h_search_avx512.h"
#include "codecs/bc6h/bc6h_tables.h"
#include "core/cpu.h"
#include "core/option_enums.h"
#include "core/parallel.h"

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace ahd {

using namespace bc6h;

namespace {

struct Block {
  int h[16][3];         // target half bits (signed: sign-magnitude as a signed int)
  float L[16][3];       // target in the error metric: sign(x)·log2(1 + |x|)
  alignas(32) float Lp[3][16];  // the same as channel planes (the AVX2 index step's texel lanes)
  double q[16][3];      // target in the c domain
  double w[16][3];      // geometry weights for the axis and least squares
  double tw[16];        // per-texel weight (for the principal axis)
  float valid[16];      // 1 for real texels, 0 for the padding of partial blocks
  int cap[3], floor_[3];  // range every decoded value must stay in (half bits, per channel)
  bool is_signed;
  // Quality `max` only (search_max): per endpoint precision (6–16 bits) and channel, the
  // extreme components whose decode stays in that range.
  int comp_hi[17][3], comp_lo[17][3];
};

// sign(x)·log2(1 + |x|) for every half-float bit pattern: the error metric, looked up.
const float* log_table() {
  static const std::vector<float> table = [] {
    std::vector<float> t(65536);
    for (uint32_t bits = 0; bits < 65536; ++bits) {
      Imath::half h;
      h.setBits(uint16_t(bits));
      float v = float(h);
      if (!std::isfinite(v)) v = std::copysign(65504.0f, v);
      // log2 in double, rounded once to float: the same table with every C runtime tried (glibc's
      // log2f and MinGW's/Wine's differ in the last bit on 3 384 of the 65 536 entries, which moved
      // a few BC6H blocks of real lightmaps between Linux and Windows; docs/platforms.md "Windows").
      t[bits] = std::copysign(float(std::log2(double(1.0f + std::fabs(v)))), v);
    }
    return t;
  }();
  return table.data();
}

// The half bits a decoded signed-int h maps to (sign-magnitude for SF16).
inline uint16_t half_bits_of(int h) { return h < 0 ? uint16_t(0x8000 | -h) : uint16_t(h); }

// Decoded half bits of c as a signed integer comparable with Block::h.
inline int decoded_h(int c, bool is_signed) {
  if (!is_signed) return (c * 31) >> 6;
  return c < 0 ? -((-c * 31) >> 5) : (c * 31) >> 5;
}

int half_signed_int(float v) {
  const uint16_t b = Imath::half(v).bits();
  return (b & 0x8000) ? -int(b & 0x7FFF) : int(b);
}

// Quantises a c-domain value to `bits`: the component whose unquantised value is closest to c
// (of floor(c·2^bits/2^16 + 0.5) and its two neighbours; on a tie the smaller).
int quantize(double c, int bits, bool is_signed) {
  if (!is_signed && bits < 15) {
    // UF16 below 15 bits, in closed form (the same choice, ≈ 5× fewer instructions: it runs for
    // every endpoint component of every candidate). With s = 2^(16 − bits), unquantize gives
    // u(0) = 0, u(k) = k·s + s/2 for 0 < k < maxv and u(maxv) = 65535, so the midpoints are
    // 0.75·s (0 | 1), (k + 1)·s (k | k + 1) and maxv·s + (s/2 − 1)/2 (maxv − 1 | maxv); a value on
    // a midpoint goes to the smaller component. Checked equal to the three-candidate search for
    // every multiple of 1/64 in [−4, 65540], ±3 ulps around every multiple of 1/4, 2 M random
    // values per precision (6–14 bits) and NaN (→ 0); callers clamp to [0, 65535] first.
    const int maxv = (1 << bits) - 1, s = 1 << (16 - bits);
    const double y = c * (1.0 / double(s));  // exact: a power of two
    if (!(y > 0.75)) return 0;
    if (c > double(maxv) * s + (s / 2 - 1) * 0.5) return maxv;
    int k = int(y);
    if (double(k) == y) --k;  // on the midpoint k·s: the smaller component
    return std::clamp(k, 1, maxv - 1);
  }
  const int minv = is_signed ? -((1 << (bits - 1)) - 1) : 0;
  const int maxv = is_signed ? (1 << (bits - 1)) - 1 : (1 << bits) - 1;
  const double x = c * (1.0 / double(1 << (16 - bits))) + 0.5;  // exact: a power of two
  int f = int(x);  // floor(x) without a library call (int() truncates towards zero)
  if (f > x) --f;
  f = std::clamp(f, minv, maxv);
  const int lo = std::max(minv, f - 1), hi = std::min(maxv, f + 1);
  int best = lo;
  double bd = std::fabs(unquantize(lo, bits, is_signed) - c);
  for (int k = lo + 1; k <= hi; ++k) {
    const double d = std::fabs(unquantize(k, bits, is_signed) - c);
    if (d < bd) bd = d, best = k;
  }
  return best;
}

// The largest component (or, with `floor`, the smallest) whose decoded half bits stay ≤ cap
// (≥ cap): unquantisation is monotonic, so a binary search finds it.
int quantize_capped(int cap, int bits, bool is_signed, bool floor) {
  const int minv = is_signed ? -((1 << (bits - 1)) - 1) : 0;
  const int maxv = is_signed ? (1 << (bits - 1)) - 1 : (1 << bits) - 1;
  int lo = minv, hi = maxv;
  auto h = [&](int k) { return decoded_h(unquantize(k, bits, is_signed), is_signed); };
  if (!floor) {
    if (h(lo) > cap) return lo;
    while (lo < hi) {  // largest k with h(k) <= cap
      const int mid = lo + (hi - lo + 1) / 2;
      if (h(mid) <= cap) lo = mid; else hi = mid - 1;
    }
    return lo;
  }
  if (h(hi) < cap) return hi;
  while (lo < hi) {  // smallest k with h(k) >= cap
    const int mid = lo + (hi - lo) / 2;
    if (h(mid) >= cap) hi = mid; else lo = mid + 1;
  }
  return lo;
}

// A candidate: mode, partition, quantised endpoints e[endpoint][channel] (absolute, epb bits).
struct Candidate {
  int mode = -1, partition = 0;
  int e[4][3] = {};
  uint8_t idx[16] = {};
  double err = 1e300;
  bool forced = false;  // fix_anchors forced an anchor index: err is not the free choice's
};

// Makes the endpoints representable: in transformed modes the others must lie within the signed
// delta range of endpoint 0 (clamped when not). Returns true when nothing had to be clamped.
bool fit_deltas(const ModeInfo& mi, int e[4][3], bool is_signed) {
  if (!mi.transformed) return true;
  bool exact = true;
  const int ends = mi.regions * 2;
  for (int c = 0; c < 3; ++c) {
    const int lo = -(1 << (mi.delta[c] - 1)), hi = (1 << (mi.delta[c] - 1)) - 1;
    for (int k = 1; k < ends; ++k) {
      const int d = std::clamp(e[k][c] - e[0][c], lo, hi);
      exact &= d == e[k][c] - e[0][c];
      e[k][c] = e[0][c] + d;
      if (is_signed) e[k][c] = std::clamp(e[k][c], -((1 << (mi.epb - 1)) - 1), (1 << (mi.epb - 1)) - 1);
      else e[k][c] = std::clamp(e[k][c], 0, (1 << mi.epb) - 1);
    }
  }
  return exact;
}

// Assigns indices and returns the weighted error of a candidate (region endpoints already fit).
// Palette entries that leave the block's range cost kOff, so a texel picks one only
// when no entry is inside; such a candidate is then unusable.
constexpr float kOff = 1e30f;

#ifdef __SSE2__
// evaluate()'s index step four palette entries at a time (SSE2 is part of x86-64): the same
// arithmetic, the minimum by min_ps and its first index from the equal lanes — what the scalar
// loop picks. Returns the error, or 1e300 when a texel has no palette entry inside the range.
double pick_indices_sse2(const Block& b, const float pal[2][3][16], uint16_t mask, int n, uint8_t idx[16]) {
  const int nv = n / 4;
  double total = 0;
  for (int t = 0; t < 16; ++t) {
    const int r = (mask >> t) & 1;
    const __m128 l0 = _mm_set1_ps(b.L[t][0]), l1 = _mm_set1_ps(b.L[t][1]), l2 = _mm_set1_ps(b.L[t][2]);
    __m128 ev[4], mn = _mm_set1_ps(std::numeric_limits<float>::infinity());
    for (int v = 0; v < nv; ++v) {
      const __m128 d0 = _mm_sub_ps(_mm_load_ps(&pal[r][0][4 * v]), l0);
      const __m128 d1 = _mm_sub_ps(_mm_load_ps(&pal[r][1][4 * v]), l1);
      const __m128 d2 = _mm_sub_ps(_mm_load_ps(&pal[r][2][4 * v]), l2);
      ev[v] = _mm_add_ps(_mm_add_ps(_mm_mul_ps(d0, d0), _mm_mul_ps(d1, d1)), _mm_mul_ps(d2, d2));
      mn = _mm_min_ps(mn, ev[v]);
    }
    mn = _mm_min_ps(mn, _mm_shuffle_ps(mn, mn, _MM_SHUFFLE(2, 3, 0, 1)));
    mn = _mm_min_ps(mn, _mm_shuffle_ps(mn, mn, _MM_SHUFFLE(1, 0, 3, 2)));
    unsigned eq = 0;
    for (int v = 0; v < nv; ++v) eq |= unsigned(_mm_movemask_ps(_mm_cmpeq_ps(ev[v], mn))) << (4 * v);
    const float e = _mm_cvtss_f32(mn);
    if (!(e < kOff)) return 1e300;  // as the scalar loop: e >= kOff
    idx[t] = uint8_t(std::countr_zero(eq));
    total += b.valid[t] * e;
  }
  return total;
}
#endif

#ifdef __SSE2__
// evaluate()'s palettes for UF16 blocks: the decoded half bits four entries at a time in float
// lanes, where every intermediate is an exact integer (below 2^23), so the palette is the scalar
// loop's (SF16 and the forced scalar path take that loop).
void palettes_uf16_sse2(const Block& b, const Candidate& cand, float pal[2][3][16]) {
  // The weights w and 64 − w as floats (exact), so no lane is converted per call.
  alignas(16) static const struct WeightLanes {
    float w[2][16], wc[2][16];  // [3-bit, 4-bit][entry]
    WeightLanes() : w(), wc() {
      for (int k = 0; k < 16; ++k) {
        if (k < 8) w[0][k] = float(kWeights3[k]), wc[0][k] = float(64 - kWeights3[k]);
        w[1][k] = float(kWeights4[k]), wc[1][k] = float(64 - kWeights4[k]);
      }
    }
  } lanes;
  const ModeInfo& mi = mode(cand.mode);
  const int n = 1 << mi.index_bits, nv = n / 4;
  const float* wl = lanes.w[mi.index_bits - 3];
  const float* wcl = lanes.wc[mi.index_bits - 3];
  const float* L = log_table();
  const __m128 inv64 = _mm_set1_ps(1.0f / 64.0f), k31 = _mm_set1_ps(31.0f), k32 = _mm_set1_ps(32.0f);
  alignas(16) int hv[3][16];
  for (int r = 0; r < mi.regions; ++r) {
    __m128i outside[4] = {_mm_setzero_si128(), _mm_setzero_si128(), _mm_setzero_si128(), _mm_setzero_si128()};
    for (int c = 0; c < 3; ++c) {
      const __m128 a = _mm_set1_ps(float(unquantize(cand.e[r * 2][c], mi.epb, false)));
      const __m128 bb = _mm_set1_ps(float(unquantize(cand.e[r * 2 + 1][c], mi.epb, false)));
      const __m128i cap = _mm_set1_epi32(b.cap[c]);
      for (int v = 0; v < nv; ++v) {
        const __m128 w = _mm_load_ps(&wl[4 * v]), wc = _mm_load_ps(&wcl[4 * v]);
        const __m128 sum = _mm_add_ps(_mm_add_ps(_mm_mul_ps(a, wc), _mm_mul_ps(bb, w)), k32);
        const __m128 ci = _mm_cvtepi32_ps(_mm_cvttps_epi32(_mm_mul_ps(sum, inv64)));  // >> 6 (non-negative)
        const __m128i h = _mm_cvttps_epi32(_mm_mul_ps(_mm_mul_ps(ci, k31), inv64));    // (c·31) >> 6
        _mm_store_si128(reinterpret_cast<__m128i*>(&hv[c][4 * v]), h);
        outside[v] = _mm_or_si128(outside[v], _mm_cmpgt_epi32(h, cap));
      }
    }
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) pal[r][c][k] = L[hv[c][k]];
    // Entries outside the range cost kOff in channel 0 (a select, no branch per entry).
    const __m128 off = _mm_set1_ps(kOff);
    for (int v = 0; v < nv; ++v) {
      const __m128 m = _mm_castsi128_ps(outside[v]);
      _mm_store_ps(&pal[r][0][4 * v], _mm_or_ps(_mm_and_ps(m, off), _mm_andnot_ps(m, _mm_load_ps(&pal[r][0][4 * v]))));
    }
  }
}
#endif

double evaluate(const Block& b, Candidate& cand) {
  const ModeInfo& mi = mode(cand.mode);
  const uint16_t mask = mi.regions == 2 ? kPartitions[cand.partition] : 0;
  const int n = 1 << mi.index_bits;
  const uint8_t* weights = mi.index_bits == 3 ? kWeights3 : kWeights4;
  const float* L = log_table();
  // Palettes as channel planes (pal[r][c][k]) so the distance loop below vectorises.
  alignas(32) float pal[2][3][16];
#ifdef __SSE2__
  // The index step: AVX2 when the CPU has it (eight entries per vector), else SSE2; the same picks.
  const auto pick = [&] {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (cpu::has(cpu::kAvx512)) return pick_indices_avx512(b.Lp, b.valid, pal, mask, n, kOff, cand.idx);
    if (cpu::has(cpu::kAvx2)) return pick_indices_avx2(b.Lp, b.valid, pal, mask, n, kOff, cand.idx);
#endif
    return pick_indices_sse2(b, pal, mask, n, cand.idx);
  };
  if (!b.is_signed && cpu::has(cpu::kSse2)) {  // UF16: the palettes in SSE2 lanes, the same values
    palettes_uf16_sse2(b, cand, pal);
    return cand.err = pick();
  }
#endif
  for (int r = 0; r < mi.regions; ++r) {
    int ua[3], ub[3];
    for (int c = 0; c < 3; ++c) {
      ua[c] = unquantize(cand.e[r * 2][c], mi.epb, b.is_signed);
      ub[c] = unquantize(cand.e[r * 2 + 1][c], mi.epb, b.is_signed);
    }
    for (int k = 0; k < n; ++k) {
      bool inside = true;
      for (int c = 0; c < 3; ++c) {
        const int h = decoded_h(interpolate(ua[c], ub[c], weights[k]), b.is_signed);
        inside &= h <= b.cap[c] && h >= b.floor_[c];
        pal[r][c][k] = L[half_bits_of(h)];
      }
      if (!inside) pal[r][0][k] = kOff;
    }
  }
  double total = 0;
#ifdef __SSE2__
  if (cpu::has(cpu::kSse2)) return cand.err = pick();
#endif
  for (int t = 0; t < 16; ++t) {
    const int r = (mask >> t) & 1;
    const float l0 = b.L[t][0], l1 = b.L[t][1], l2 = b.L[t][2];
    float e[16] = {};
    for (int k = 0; k < n; ++k) {
      const float d0 = pal[r][0][k] - l0, d1 = pal[r][1][k] - l1, d2 = pal[r][2][k] - l2;
      e[k] = d0 * d0 + d1 * d1 + d2 * d2;
    }
    int bi = 0;
    for (int k = 1; k < n; ++k)
      if (e[k] < e[bi]) bi = k;
    if (e[bi] >= kOff) {  // no palette entry within the block's range: not a usable candidate
      cand.err = 1e300;
      return cand.err;
    }
    cand.idx[t] = uint8_t(bi);
    total += b.valid[t] * e[bi];
  }
  cand.err = total;
  return total;
}

// The anchors (texel 0, and region 1's anchor) must have an index with a zero top bit: where one
// does not, swap that region's endpoints and mirror its indices (the palette is symmetric, so the
// decode is unchanged), then restore the delta constraints and re-evaluate if they moved.
void fix_anchors(const Block& b, Candidate& cand) {
  const ModeInfo& mi = mode(cand.mode);
  const int n = 1 << mi.index_bits;
  const uint16_t mask = mi.regions == 2 ? kPartitions[cand.partition] : 0;
  const int anchors[2] = {0, mi.regions == 2 ? kAnchor2[cand.partition] : 0};
  bool swapped = false;
  for (int r = 0; r < mi.regions; ++r) {
    if (cand.idx[anchors[r]] < n / 2) continue;
    for (int c = 0; c < 3; ++c) std::swap(cand.e[r * 2][c], cand.e[r * 2 + 1][c]);
    for (int t = 0; t < 16; ++t)
      if (int((mask >> t) & 1) == r) cand.idx[t] = uint8_t(n - 1 - cand.idx[t]);
    swapped = true;
  }
  if (!swapped) return;
  int before[4][3];
  std::memcpy(before, cand.e, sizeof before);
  fit_deltas(mi, cand.e, b.is_signed);
  if (std::memcmp(before, cand.e, sizeof before) != 0) {
    // The swap broke a delta: re-evaluate, and if an anchor flips again keep the safe ordering by
    // forcing its index into the lower half (a valid, slightly worse block).
    evaluate(b, cand);
    for (int r = 0; r < mi.regions; ++r)
      if (cand.idx[anchors[r]] >= n / 2) cand.idx[anchors[r]] = uint8_t(n / 2 - 1);
    cand.forced = true;
    // Recompute the error for the indices we will actually write.
    const uint8_t* weights = mi.index_bits == 3 ? kWeights3 : kWeights4;
    const float* L = log_table();
    double total = 0;
    for (int t = 0; t < 16; ++t) {
      const int r = (mask >> t) & 1;
      for (int c = 0; c < 3; ++c) {
        const int ua = unquantize(cand.e[r * 2][c], mi.epb, b.is_signed), ub = unquantize(cand.e[r * 2 + 1][c], mi.epb, b.is_signed);
        const int h = decoded_h(interpolate(ua, ub, weights[cand.idx[t]]), b.is_signed);
        if (h > b.cap[c] || h < b.floor_[c]) {  // the forced index left the block's range
          cand.err = 1e300;
          return;
        }
        const double d = L[half_bits_of(h)] - b.L[t][c];
        total += b.valid[t] * d * d;
      }
    }
    cand.err = total;
  }
}

// Principal axis endpoints of the texels of region r (c domain).
void axis_endpoints(const Block& b, uint16_t mask, int r, double lo[3], double hi[3]) {
  double sw = 0, mean[3] = {0, 0, 0};
  for (int t = 0; t < 16; ++t) {
    if (int((mask >> t) & 1) != r) continue;
    sw += b.tw[t];
    for (int c = 0; c < 3; ++c) mean[c] += b.tw[t] * b.q[t][c];
  }
  if (sw <= 0) sw = 1;
  for (double& m : mean) m /= sw;
  double cov[3][3] = {};
  for (int t = 0; t < 16; ++t) {
    if (int((mask >> t) & 1) != r) continue;
    double d[3];
    for (int c = 0; c < 3; ++c) d[c] = b.q[t][c] - mean[c];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov[i][j] += b.tw[t] * d[i] * d[j];
  }
  double axis[3] = {1, 1, 1};
  for (int it = 0; it < 6; ++it) {
    double v[3];
    for (int i = 0; i < 3; ++i) v[i] = cov[i][0] * axis[0] + cov[i][1] * axis[1] + cov[i][2] * axis[2];
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len < 1e-12) break;
    for (int i = 0; i < 3; ++i) axis[i] = v[i] / len;
  }
  const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& a : axis) a /= len;
  double tmin = 1e30, tmax = -1e30;
  for (int t = 0; t < 16; ++t) {
    if (int((mask >> t) & 1) != r) continue;
    double p = 0;
    for (int c = 0; c < 3; ++c) p += (b.q[t][c] - mean[c]) * axis[c];
    tmin = std::min(tmin, p), tmax = std::max(tmax, p);
  }
  if (tmin > tmax) tmin = tmax = 0;
  for (int c = 0; c < 3; ++c) lo[c] = mean[c] + tmin * axis[c], hi[c] = mean[c] + tmax * axis[c];
}

// axis_endpoints for both regions of a partition: t[r][0], t[r][1] = region r's lo and hi. The
// same operations per region in the same order (each texel's sums go to its region's
// accumulators, no branch), the two regions' power steps side by side so that their square roots
// and divisions overlap.
void axis_endpoints_pair(const Block& b, uint16_t mask, double t[2][2][3]) {
  double mean[2][3] = {}, cov[2][3][3] = {};
#if defined(__SSE2__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  const bool wide = cpu::has(cpu::kSse2 | cpu::kAvx2);
#else
  const bool wide = false;
#endif
  if (wide) {
    region_moments_pair_avx2(b.q, b.tw, mask, mean, cov);  // the same sums, four lanes at a time
  } else {
    double sw[2] = {0, 0};
    for (int k = 0; k < 16; ++k) {
      const int r = (mask >> k) & 1;
      sw[r] += b.tw[k];
      for (int c = 0; c < 3; ++c) mean[r][c] += b.tw[k] * b.q[k][c];
    }
    for (int r = 0; r < 2; ++r) {
      if (sw[r] <= 0) sw[r] = 1;
      for (double& m : mean[r]) m /= sw[r];
    }
    for (int k = 0; k < 16; ++k) {
      const int r = (mask >> k) & 1;
      double d[3];
      for (int c = 0; c < 3; ++c) d[c] = b.q[k][c] - mean[r][c];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) cov[r][i][j] += b.tw[k] * d[i] * d[j];
    }
  }
  double axis[2][3] = {{1, 1, 1}, {1, 1, 1}};
  bool done[2] = {false, false};
  for (int it = 0; it < 6; ++it)
    for (int r = 0; r < 2; ++r) {
      if (done[r]) continue;
      double v[3];
      for (int i = 0; i < 3; ++i) v[i] = cov[r][i][0] * axis[r][0] + cov[r][i][1] * axis[r][1] + cov[r][i][2] * axis[r][2];
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (len < 1e-12) {
        done[r] = true;
        continue;
      }
      for (int i = 0; i < 3; ++i) axis[r][i] = v[i] / len;
    }
  double tmin[2] = {1e30, 1e30}, tmax[2] = {-1e30, -1e30};
  for (int r = 0; r < 2; ++r) {
    const double len = std::sqrt(axis[r][0] * axis[r][0] + axis[r][1] * axis[r][1] + axis[r][2] * axis[r][2]);
    for (double& a : axis[r]) a /= len;
  }
  for (int k = 0; k < 16; ++k) {
    const int r = (mask >> k) & 1;
    double p = 0;
    for (int c = 0; c < 3; ++c) p += (b.q[k][c] - mean[r][c]) * axis[r][c];
    tmin[r] = std::min(tmin[r], p), tmax[r] = std::max(tmax[r], p);
  }
  for (int r = 0; r < 2; ++r) {
    if (tmin[r] > tmax[r]) tmin[r] = tmax[r] = 0;
    for (int c = 0; c < 3; ++c)
      t[r][0][c] = mean[r][c] + tmin[r] * axis[r][c], t[r][1][c] = mean[r][c] + tmax[r] * axis[r][c];
  }
}

// Weighted first and second moments of texels, summed per region by partition masks.
struct Moments {
  double w, s[3], ss[6];  // ss: xx yy zz xy xz yz
  void add(const Moments& o, double sign) {
    w += sign * o.w;
    for (int i = 0; i < 3; ++i) s[i] += sign * o.s[i];
    for (int i = 0; i < 6; ++i) ss[i] += sign * o.ss[i];
  }
};

Moments texel_moments(const Block& b, int t) {
  const double w = b.tw[t];
  const double* q = b.q[t];
  return {w, {w * q[0], w * q[1], w * q[2]}, {w * q[0] * q[0], w * q[1] * q[1], w * q[2] * q[2], w * q[0] * q[1], w * q[0] * q[2], w * q[1] * q[2]}};
}

// A region's (weighted) covariance of the half-bit values and its trace, from its moments (m.w > 0).
struct Covariance {
  double xx, yy, zz, xy, xz, yz, trace;
};
Covariance covariance_of(const Moments& m) {
  const double inv = 1.0 / m.w;
  Covariance k;
  k.xx = m.ss[0] - m.s[0] * m.s[0] * inv, k.yy = m.ss[1] - m.s[1] * m.s[1] * inv;
  k.zz = m.ss[2] - m.s[2] * m.s[2] * inv, k.xy = m.ss[3] - m.s[0] * m.s[1] * inv;
  k.xz = m.ss[4] - m.s[0] * m.s[2] * inv, k.yz = m.ss[5] - m.s[1] * m.s[2] * inv;
  k.trace = k.xx + k.yy + k.zz;
  return k;
}

// Residual of fitting a region's texels by a line: trace of the covariance minus its principal
// eigenvalue, estimated by the Rayleigh quotient after three power steps (no square roots: this
// runs for all 64 regions of every block).
double line_residual(const Moments& m) {
  if (m.w <= 0) return 0;
  const Covariance k = covariance_of(m);
  const double xx = k.xx, yy = k.yy, zz = k.zz, xy = k.xy, xz = k.xz, yz = k.yz, trace = k.trace;
  if (!(trace > 0)) return 0;
  // Power steps from three orthogonal starts in turn: one of them is not orthogonal to the
  // principal axis. Scaled by 1/trace each step so that nothing overflows.
  static const double starts[3][3] = {{1, 1, 1}, {1, -1, 0}, {1, 1, -2}};
  double lambda = 0;
  for (const auto& s0 : starts) {
    double v[3] = {s0[0], s0[1], s0[2]};
    for (int it = 0; it < 3; ++it) {
      const double u[3] = {(xx * v[0] + xy * v[1] + xz * v[2]) / trace, (xy * v[0] + yy * v[1] + yz * v[2]) / trace,
                           (xz * v[0] + yz * v[1] + zz * v[2]) / trace};
      std::memcpy(v, u, sizeof v);
    }
    const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (vv < 1e-20) continue;
    const double cv[3] = {xx * v[0] + xy * v[1] + xz * v[2], xy * v[0] + yy * v[1] + yz * v[2],
                          xz * v[0] + yz * v[1] + zz * v[2]};
    lambda = (v[0] * cv[0] + v[1] * cv[1] + v[2] * cv[2]) / vv;
    break;
  }
  return std::max(0.0, trace - lambda);
}

// The same residual, cheaper (quality `default`): two power steps from the covariance's column of
// largest variance (never orthogonal to the principal axis unless the matrix is diagonal, where
// it is that axis), no scaling inside the loop (double cannot overflow on half-range values).
double line_residual_quick(const Moments& m) {
  if (m.w <= 0) return 0;
  const Covariance k = covariance_of(m);
  const double xx = k.xx, yy = k.yy, zz = k.zz, xy = k.xy, xz = k.xz, yz = k.yz, trace = k.trace;
  if (!(trace > 0)) return 0;
  double v[3] = {xx, xy, xz};
  if (yy > xx && yy >= zz) v[0] = xy, v[1] = yy, v[2] = yz;
  else if (zz > xx && zz > yy) v[0] = xz, v[1] = yz, v[2] = zz;
  for (int it = 0; it < 2; ++it) {
    const double u0 = xx * v[0] + xy * v[1] + xz * v[2], u1 = xy * v[0] + yy * v[1] + yz * v[2],
                 u2 = xz * v[0] + yz * v[1] + zz * v[2];
    v[0] = u0, v[1] = u1, v[2] = u2;
  }
  const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (!(vv > 0)) return trace;
  const double cv0 = xx * v[0] + xy * v[1] + xz * v[2], cv1 = xy * v[0] + yy * v[1] + yz * v[2],
               cv2 = xz * v[0] + yz * v[1] + zz * v[2];
  return std::max(0.0, trace - (v[0] * cv0 + v[1] * cv1 + v[2] * cv2) / vv);
}

#ifdef __SSE2__
// line_residual_quick(a) + line_residual_quick(b), the two regions in the two lanes of SSE2
// doubles: the same operations in the same order, the early returns as final selects. `m` holds
// the moments in lanes (region a, region b): w, s[0..2], ss[0..5].
double pair_residual_sse2(const __m128d m[10]) {
  auto sel = [](__m128d mask, __m128d yes, __m128d no) { return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no)); };
  const __m128d zero = _mm_setzero_pd();
  const __m128d w = m[0], inv = _mm_div_pd(_mm_set1_pd(1.0), w);
  const __m128d s0 = m[1], s1 = m[2], s2 = m[3];
  auto cov = [&](int i, __m128d x, __m128d y) {
    return _mm_sub_pd(m[4 + i], _mm_mul_pd(_mm_mul_pd(x, y), inv));
  };
  const __m128d xx = cov(0, s0, s0), yy = cov(1, s1, s1), zz = cov(2, s2, s2), xy = cov(3, s0, s1),
                xz = cov(4, s0, s2), yz = cov(5, s1, s2);
  const __m128d trace = _mm_add_pd(_mm_add_pd(xx, yy), zz);
  const __m128d c1 = _mm_and_pd(_mm_cmpgt_pd(yy, xx), _mm_cmpge_pd(yy, zz));
  const __m128d c2 = _mm_andnot_pd(c1, _mm_and_pd(_mm_cmpgt_pd(zz, xx), _mm_cmpgt_pd(zz, yy)));
  __m128d v0 = sel(c1, xy, sel(c2, xz, xx)), v1 = sel(c1, yy, sel(c2, yz, xy)), v2 = sel(c1, yz, sel(c2, zz, xz));
  auto row = [](__m128d p, __m128d q, __m128d r, __m128d x, __m128d y, __m128d z) {
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(p, x), _mm_mul_pd(q, y)), _mm_mul_pd(r, z));
  };
  for (int it = 0; it < 2; ++it) {
    const __m128d u0 = row(xx, xy, xz, v0, v1, v2), u1 = row(xy, yy, yz, v0, v1, v2), u2 = row(xz, yz, zz, v0, v1, v2);
    v0 = u0, v1 = u1, v2 = u2;
  }
  const __m128d vv = row(v0, v1, v2, v0, v1, v2);
  const __m128d cv0 = row(xx, xy, xz, v0, v1, v2), cv1 = row(xy, yy, yz, v0, v1, v2), cv2 = row(xz, yz, zz, v0, v1, v2);
  __m128d r = _mm_max_pd(_mm_sub_pd(trace, _mm_div_pd(row(v0, v1, v2, cv0, cv1, cv2), vv)), zero);
  r = sel(_mm_cmpgt_pd(vv, zero), r, trace);          // !(vv > 0): trace
  r = sel(_mm_cmpgt_pd(trace, zero), r, zero);        // !(trace > 0): 0
  r = sel(_mm_cmpgt_pd(w, zero), r, zero);            // w <= 0: 0
  alignas(16) double out[2];
  _mm_store_pd(out, r);
  return out[0] + out[1];
}
#endif

// Least squares for one region's unquantised endpoints given the indices; writes c-domain targets.
// The three channels in one pass over the region's texels (each channel's sums in texel order, as
// one pass per channel would add them: the same doubles).
bool refit_region(const Block& b, const Candidate& cand, int r, double lo[3], double hi[3]) {
  const ModeInfo& mi = mode(cand.mode);
  const unsigned mask = mi.regions == 2 ? kPartitions[cand.partition] : 0;
  const uint8_t* weights = mi.index_bits == 3 ? kWeights3 : kWeights4;
  double s00[3] = {}, s01[3] = {}, s11[3] = {}, t0[3] = {}, t1[3] = {};
  for (int t = 0; t < 16; ++t) {
    if (int((mask >> t) & 1) != r) continue;
    const double f = weights[cand.idx[t]] / 64.0, g = 1 - f;
    for (int c = 0; c < 3; ++c) {
      const double w = b.w[t][c] + 1e-12, wg = w * g, wf = w * f;
      s00[c] += wg * g, s01[c] += wg * f, s11[c] += wf * f;
      t0[c] += wg * b.q[t][c], t1[c] += wf * b.q[t][c];
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double det = s00[c] * s11[c] - s01[c] * s01[c];
    if (std::fabs(det) < 1e-12 * (s00[c] * s11[c] + 1e-30)) return false;
    lo[c] = (t0[c] * s11[c] - s01[c] * t1[c]) / det;
    hi[c] = (s00[c] * t1[c] - s01[c] * t0[c]) / det;
  }
  return true;
}

// Builds, quantises and evaluates a candidate from c-domain endpoint targets per region. With
// `only_if_exact`, a mode whose deltas would need clamping is not evaluated (returns false).
// `same` (refinement): when the quantised endpoints are `same`'s, `same` itself is the result
// (its error is what evaluating them again gives) unless its anchors were forced.
bool make_candidate(const Block& b, int m, int partition, const double targets[2][2][3], Candidate& out,
                    bool only_if_exact = false, const Candidate* same = nullptr) {
  const ModeInfo& mi = mode(m);
  out.mode = m;
  out.partition = partition;
  const double lim = b.is_signed ? 0x7FFF : 0xFFFF, low = b.is_signed ? -0x7FFF : 0;
  if (only_if_exact && mi.transformed) {
    // Quantising moves an endpoint by under two steps, so a target delta this far out of range
    // cannot fit: skip the mode before quantising anything.
    const double step = double(1 << (16 - mi.epb));  // the same for UF16 and SF16 (unquantize)
    for (int c = 0; c < 3; ++c) {
      const double reach = ((1 << (mi.delta[c] - 1)) + 2) * step;
      const double t0 = std::clamp(targets[0][0][c], low, lim);
      for (int e = 1; e < mi.regions * 2; ++e)
        if (std::fabs(std::clamp(targets[e / 2][e % 2][c], low, lim) - t0) > reach) {
          out.err = 1e300;
          return false;
        }
    }
  }
  for (int r = 0; r < mi.regions; ++r)
    for (int k = 0; k < 2; ++k)
      for (int c = 0; c < 3; ++c) out.e[r * 2 + k][c] = quantize(std::clamp(targets[r][k][c], low, lim), mi.epb, b.is_signed);
  if (!fit_deltas(mi, out.e, b.is_signed) && only_if_exact) {
    out.err = 1e300;
    return false;
  }
  if (same && !same->forced && std::memcmp(out.e, same->e, sizeof out.e) == 0) {
    out = *same;
    return true;
  }
  evaluate(b, out);
  fix_anchors(b, out);
  return true;
}

// Refinement passes: least squares on the indices, re-quantise, keep improvements.
void refine(const Block& b, Candidate& best, int passes, bool perturb) {
  const ModeInfo& mi = mode(best.mode);
  for (int p = 0; p < passes; ++p) {
    double t[2][2][3];
    bool ok = true;
    for (int r = 0; r < mi.regions && ok; ++r) ok = refit_region(b, best, r, t[r][0], t[r][1]);
    if (!ok) break;
    Candidate c;
    make_candidate(b, best.mode, best.partition, t, c, false, &best);  // unchanged endpoints: no gain
    if (c.err < best.err) best = c;
    else break;
  }
  if (!perturb) return;
  // ±1 on each quantised endpoint component, greedily.
  for (int k = 0; k < mi.regions * 2; ++k)
    for (int ch = 0; ch < 3; ++ch)
      for (int d : {-1, 1}) {
        Candidate c = best;
        c.e[k][ch] += d;
        if (!fit_deltas(mi, c.e, b.is_signed)) continue;
        const int maxv = b.is_signed ? (1 << (mi.epb - 1)) - 1 : (1 << mi.epb) - 1;
        if (c.e[k][ch] > maxv || c.e[k][ch] < (b.is_signed ? -maxv : 0)) continue;
        evaluate(b, c);
        fix_anchors(b, c);
        if (c.err < best.err) best = c;
      }
}

// Quality `default`'s polish: coordinate descent over `best`'s quantised endpoints with its
// indices held. With the indices held, each channel's error depends only on that channel's
// endpoint components, so a ±1 step costs one lookup per (region, index) group of that channel
// instead of a whole evaluation. Each component is tried one step each way, then moved further
// while that pays, up to `rounds` steps. A step is kept when it lowers its channel's judged error,
// every texel's held palette entry stays inside the block's range (no specks) and the deltas
// still fit. Returns whether anything moved; `gain` (when given) gets the error removed, so
// best.err − gain is the polished block's judged error with the held indices. Anchors are
// unchanged (the indices are).
bool polish_steps(const Block& b, Candidate& best, int rounds, double* gain = nullptr) {
  const ModeInfo& mi = mode(best.mode);
  const uint16_t mask = mi.regions == 2 ? kPartitions[best.partition] : 0;
  const uint8_t* weights = mi.index_bits == 3 ? kWeights3 : kWeights4;
  const float* L = log_table();
  const int ends = mi.regions * 2;
  const int maxv = (1 << mi.epb) - 1;  // UF16 only
  // Texels sharing a region and an index decode to the same value v, so their error is
  // n·(v − m)² plus a constant, with n their count and m the mean of their targets: one palette
  // lookup per group instead of one per texel, and no cancellation in float.
  int ng = 0, slot[32], greg[16], gwa[16], gwb[16];
  alignas(32) float gn[16], gm[3][16];
  std::fill(slot, slot + 32, -1);
  for (int t = 0; t < 16; ++t) {  // padding texels too, with no weight: their entries stay in range
    const int r = (mask >> t) & 1, key = r * 16 + best.idx[t];
    if (slot[key] < 0) {
      slot[key] = ng;
      greg[ng] = 2 * r, gwb[ng] = weights[best.idx[t]], gwa[ng] = 64 - gwb[ng];
      gn[ng] = 0, gm[0][ng] = gm[1][ng] = gm[2][ng] = 0;
      ++ng;
    }
    const int i = slot[key];
    gn[i] += b.valid[t];
    for (int c = 0; c < 3; ++c) gm[c][i] += b.valid[t] * b.L[t][c];
  }
  // Group means; padding up to a multiple of four (eight for AVX2) repeats group 0 with no weight
  // (adds 0).
  const int ng4 = (ng + 3) & ~3, ng8 = (ng + 7) & ~7;
  for (int i = 0; i < ng8; ++i) {
    if (i >= ng) {
      greg[i] = greg[0], gwa[i] = gwa[0], gwb[i] = gwb[0], gn[i] = 0;
      for (auto& m : gm) m[i] = 0;
      continue;
    }
    for (auto& m : gm) m[i] = gn[i] > 0 ? m[i] / gn[i] : 0.0f;
  }
  // The groups' weights and regions as float lanes (read by the SSE2/AVX2 code only).
  [[maybe_unused]] alignas(32) float fwa[16], fwb[16], fr[16];
  for (int i = 0; i < ng8; ++i) fwa[i] = float(gwa[i]), fwb[i] = float(gwb[i]), fr[i] = float(greg[i] / 2);
  [[maybe_unused]] const bool simd = cpu::has(cpu::kSse2);
#if defined(__SSE2__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  const bool wide = cpu::has(cpu::kSse2 | cpu::kAvx2);
#else
  [[maybe_unused]] const bool wide = false;
#endif
  Candidate& c = best;
  bool moved = false;
  for (int ch = 0; ch < 3; ++ch) {
    const int cap = b.cap[ch];
    // Channel ch's judged error, less its constant Q, for unquantised components u; +inf when a
    // decoded value leaves the block's range.
    auto channel_error = [&](const int u[4]) {
      alignas(16) float part[4] = {0, 0, 0, 0};
      bool over = false;
#if defined(__SSE2__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
      if (wide) {  // eight groups at a time, the same sums (held_channel_error_avx2)
        const float e = held_channel_error_avx2(u, ng, fr, fwa, fwb, gn, gm[ch], cap, L, &over);
        return over ? std::numeric_limits<float>::infinity() : e;
      }
#endif
#ifdef __SSE2__
      if (simd) {  // four groups at a time; the decoded values in exact float lanes (as palettes_uf16_sse2)
        const __m128 a0 = _mm_set1_ps(float(u[0])), b0 = _mm_set1_ps(float(u[1]));
        const __m128 da = _mm_set1_ps(float(u[2] - u[0])), db = _mm_set1_ps(float(u[3] - u[1]));
        const __m128 inv64 = _mm_set1_ps(1.0f / 64.0f), k31 = _mm_set1_ps(31.0f), k32 = _mm_set1_ps(32.0f);
        const __m128i capv = _mm_set1_epi32(cap);
        __m128 acc = _mm_setzero_ps();
        __m128i out = _mm_setzero_si128();
        alignas(16) int hv[4];
        for (int i = 0; i < ng; i += 4) {
          const __m128 r = _mm_load_ps(&fr[i]);
          const __m128 a = _mm_add_ps(a0, _mm_mul_ps(r, da)), bb = _mm_add_ps(b0, _mm_mul_ps(r, db));
          const __m128 sum = _mm_add_ps(_mm_add_ps(_mm_mul_ps(a, _mm_load_ps(&fwa[i])), _mm_mul_ps(bb, _mm_load_ps(&fwb[i]))), k32);
          const __m128 ci = _mm_cvtepi32_ps(_mm_cvttps_epi32(_mm_mul_ps(sum, inv64)));
          const __m128i h = _mm_cvttps_epi32(_mm_mul_ps(_mm_mul_ps(ci, k31), inv64));
          out = _mm_or_si128(out, _mm_cmpgt_epi32(h, capv));
          _mm_store_si128(reinterpret_cast<__m128i*>(hv), h);
          const __m128 d = _mm_sub_ps(_mm_setr_ps(L[hv[0]], L[hv[1]], L[hv[2]], L[hv[3]]), _mm_load_ps(&gm[ch][i]));
          acc = _mm_add_ps(acc, _mm_mul_ps(_mm_mul_ps(_mm_load_ps(&gn[i]), d), d));
        }
        _mm_store_ps(part, acc);
        over = _mm_movemask_epi8(out) != 0;
      } else
#endif
        for (int i = 0; i < ng4; ++i) {
          const int h = (((u[greg[i]] * gwa[i] + u[greg[i] + 1] * gwb[i] + 32) >> 6) * 31) >> 6;
          over |= h > cap;
          const float d = L[h] - gm[ch][i];
          part[i & 3] += (gn[i] * d) * d;
        }
      return over ? std::numeric_limits<float>::infinity() : (part[0] + part[1]) + (part[2] + part[3]);
    };
    int u[4] = {};
    for (int k = 0; k < ends; ++k) u[k] = unquantize(c.e[k][ch], mi.epb, false);
    float cur = channel_error(u);
    const float start = cur;
    const int dlo = mi.transformed ? -(1 << (mi.delta[ch] - 1)) : -maxv, dhi = mi.transformed ? -dlo - 1 : maxv;
    // Whether endpoint k's component may move one step in direction d.
    auto feasible = [&](int k, int d) {
      const int v = c.e[k][ch] + d;
      if (v < 0 || v > maxv) return false;
      for (int j = 1; j < ends; ++j) {  // every delta from endpoint 0 must still fit
        const int dj = (j == k ? v : c.e[j][ch]) - (k == 0 ? v : c.e[0][ch]);
        if (dj < dlo || dj > dhi) return false;
      }
      return true;
    };
    // Tries endpoint k's component one step in direction d; keeps it when the error drops.
    auto step = [&](int k, int d) {
      if (!feasible(k, d)) return false;
      const int v = c.e[k][ch] + d;
      const int keep = u[k];
      u[k] = unquantize(v, mi.epb, false);
      const float err = channel_error(u);
      if (!(err < cur)) {
        u[k] = keep;
        return false;
      }
      cur = err, c.e[k][ch] = v, moved = true;
      return true;
    };
    // Both directions once per component, then further steps only where a step paid.
    int dir[4] = {0, 0, 0, 0};
    for (int k = 0; k < ends; ++k) {
#if defined(__SSE2__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
      if (wide && feasible(k, -1) && feasible(k, 1)) {
        // Both steps' errors in one call (the up step's is computed even when the down step
        // wins, and then unused): the same errors and choices as step(k, −1), then step(k, 1),
        // without the dependence between them.
        int ud[4], uu[4];
        std::memcpy(ud, u, sizeof ud), std::memcpy(uu, u, sizeof uu);
        ud[k] = unquantize(c.e[k][ch] - 1, mi.epb, false), uu[k] = unquantize(c.e[k][ch] + 1, mi.epb, false);
        float e2[2];
        bool o2[2];
        held_channel_error_pair_avx2(ud, uu, ng, fr, fwa, fwb, gn, gm[ch], cap, L, e2, o2);
        const float down = o2[0] ? std::numeric_limits<float>::infinity() : e2[0];
        const float up = o2[1] ? std::numeric_limits<float>::infinity() : e2[1];
        dir[k] = down < cur ? -1 : up < cur ? 1 : 0;
        if (dir[k] != 0) {
          cur = dir[k] < 0 ? down : up, u[k] = dir[k] < 0 ? ud[k] : uu[k];
          c.e[k][ch] += dir[k], moved = true;
        }
        continue;
      }
#endif
      dir[k] = step(k, -1) ? -1 : step(k, 1) ? 1 : 0;
    }
    for (int round = 1; round < rounds; ++round) {
      bool any = false;
      for (int k = 0; k < ends; ++k)
        if (dir[k] != 0) {
          if (!step(k, dir[k])) dir[k] = 0;
          any |= dir[k] != 0;
        }
      if (!any) break;
    }
    if (gain) *gain += start - cur;
  }
  return moved;
}

// polish_steps on a copy of `best`, then the indices re-picked (every palette entry); the copy
// replaces `best` only when its error is lower, so the error never rises.
void polish(const Block& b, Candidate& best, int rounds) {
  Candidate c = best;
  if (!polish_steps(b, c, rounds)) return;
  evaluate(b, c);
  fix_anchors(b, c);
  if (c.err < best.err) best = c;
}

// Bits in order from bit 0 of byte 0, in two 64-bit words written out at the end (a 128-bit
// shift per field cost a third of pack's instructions).
struct BitWriter {
  uint64_t v[2] = {0, 0};
  int pos = 0;
  void put(int x, int n) {  // 1 ≤ n ≤ 31, pos + n ≤ 128
    const uint64_t bits = uint64_t(unsigned(x) & ((1u << n) - 1));
    const int at = pos & 63;
    v[pos >> 6] |= bits << at;
    if (at + n > 64) v[1] |= bits >> (64 - at);  // a field across the two words
    pos += n;
  }
  void write(uint8_t out[16]) const {
    for (int i = 0; i < 16; ++i) out[i] = uint8_t(v[i >> 3] >> (8 * (i & 7)));
  }
};

void pack(const Candidate& c, bool is_signed, uint8_t out[16]) {
  const ModeInfo& mi = mode(c.mode);
  BitWriter w;
  w.put(mi.code, mi.code < 2 ? 2 : 5);
  int f[12];
  for (int k = 0; k < 4; ++k)
    for (int ch = 0; ch < 3; ++ch) f[k * 3 + ch] = c.e[k][ch];
  const int ends = mi.regions * 2;
  for (int ch = 0; ch < 3; ++ch)
    for (int k = 1; k < ends; ++k) {
      int& v = f[k * 3 + ch];
      if (mi.transformed) v = (v - f[ch]) & ((1 << mi.delta[ch]) - 1);
      else v &= (1 << mi.epb) - 1;
    }
  for (int ch = 0; ch < 3; ++ch) f[ch] &= (1 << mi.epb) - 1;
  (void)is_signed;
  for (int i = 0; i < mi.layout_count; ++i) {
    const int field = mi.layout_field[i], bit = mi.layout_bit[i];
    const int v = field == D ? c.partition : f[field];
    w.put((v >> bit) & 1, 1);
  }
  const int anchor = mi.regions == 2 ? kAnchor2[c.partition] : -1;
  for (int t = 0; t < 16; ++t) w.put(c.idx[t], (t == 0 || t == anchor) ? mi.index_bits - 1 : mi.index_bits);
  w.write(out);
}

// Modes by endpoint precision, most precise first.
const int kOneRegionOrder[4] = {13, 12, 11, 10};
const int kTwoRegionOrder[10] = {2, 3, 4, 0, 5, 6, 7, 8, 1, 9};

// Evaluates modes in precision order, keeping the two best in `top`. Modes whose deltas need
// clamping are skipped, and after `max_exact` modes that fit exactly the rest are not tried (a
// less precise mode rarely wins; 0 = try all). The last mode of each order never needs deltas.
void try_modes(const Block& b, const int* order, int count, int partition, const double t[2][2][3], int max_exact,
               Candidate top[2]) {
  int exact = 0;
  for (int i = 0; i < count; ++i) {
    Candidate c;
    const bool last = i == count - 1;
    if (!make_candidate(b, order[i], partition, t, c, /*only_if_exact=*/max_exact > 0 && !last)) continue;
    if (c.err < top[0].err) top[1] = top[0], top[0] = c;
    else if (c.err < top[1].err) top[1] = c;
    if (max_exact > 0 && ++exact >= max_exact) break;
  }
}

// A candidate that is always valid: one region, 10-bit endpoints on the per-channel range,
// rounded inwards, so every palette entry lies inside the block's range.
Candidate in_range_candidate(const Block& b) {
  Candidate c;
  c.mode = 10;
  for (int ch = 0; ch < 3; ++ch) {
    int lo = 1 << 30;
    for (int t = 0; t < 16; ++t)
      if (b.valid[t] > 0) lo = std::min(lo, b.h[t][ch]);
    c.e[0][ch] = quantize_capped(lo, 10, b.is_signed, /*floor=*/true);
    c.e[1][ch] = quantize_capped(b.cap[ch] - 1, 10, b.is_signed, /*floor=*/false);
    if (decoded_h(unquantize(c.e[0][ch], 10, b.is_signed), b.is_signed) > b.cap[ch]) c.e[0][ch] = c.e[1][ch];
  }
  evaluate(b, c);
  fix_anchors(b, c);
  return c;
}

void try_two_regions(const Block& b, int n_parts, int max_exact, int refine_top, int passes, bool perturb,
                     Candidate& best, bool quick = false, double incumbent_err = 1e300);

// Quality `default`'s pruning (see encode_block_default).
constexpr float kFastGood = 3000.0f;
constexpr double kTwoRegionWorth = 6e-3;
constexpr double kTwoLineGain = 0.30;
constexpr double kNoiseBand[2] = {1.0 / 8192, 1.0 / 256}, kNoiseErr = 0.5;
// Dark blocks (issue 28): kTwoRegionWorth and kNoiseErr are errors in the judged metric, whose
// slope falls with the value below 1 (log2(1+x) ≈ x/ln 2), so on a dark block every error is
// small and the two gates skipped nearly all of a real lightmap's blocks (the Godot bakes of
// bench/data/real are mostly below 0.1). Both gates are scaled by min(1, (s/kDarkRef)²), s the
// block's mean x/(1+x): a relative error for blocks darker than x = 1/3, unchanged above.
constexpr double kDarkRef = 0.25;
// Byte-changing skips (issue 13, `default` on hard): the second-ranked partition's candidate is
// refined only when its unrefined error is within kRefineSecond times the best so far (the
// incumbent included), and the incumbent's least squares are skipped when two regions already
// beat it kTwoRegionsClear times over. Hard: 164 M → 152 M instructions (callgrind, AVX2 path,
// with the skipped second polish below), log-RMSE 0.0079383 →
// 0.0079432 (bound 0.00795). The same skip on the first partition (within 2×) saved 0.6 M more
// but cost smooth 0.00831 → 0.00850.
constexpr double kRefineSecond = 1.2, kTwoRegionsClear = 0.4;
constexpr int kOneRegionPasses = 2, kPartitionsTried = 2, kTwoRegionPasses = 2, kPolishRounds = 4;

Candidate search(const Block& b, Bc6hQuality q) {
  Candidate best = in_range_candidate(b);

  const int passes = q == Bc6hQuality::Fast ? 0 : q == Bc6hQuality::Default ? 2 : q == Bc6hQuality::High ? 4 : 6;
  const int refine_top = q == Bc6hQuality::Fast ? 0 : q == Bc6hQuality::Default ? 1 : 2;  // candidates refined per group
  const int max_exact = q == Bc6hQuality::Max ? 0 : q == Bc6hQuality::High ? 3 : 2;     // modes tried per group
  const bool perturb = q == Bc6hQuality::Max;

  // One region: modes 11–14 (indices 10..13).
  {
    double t[2][2][3];
    axis_endpoints(b, 0, 0, t[0][0], t[0][1]);
    Candidate top[2];
    try_modes(b, kOneRegionOrder, 4, 0, t, max_exact, top);
    for (int k = 0; k < 2; ++k) {
      Candidate& c = top[k];
      if (c.mode < 0) continue;
      if (k < refine_top) refine(b, c, passes, perturb);
      if (c.err < best.err) best = c;
    }
  }
  if (best.err <= 0) return best;

  const int n_parts = q == Bc6hQuality::Fast ? 1 : q == Bc6hQuality::Default ? 2 : q == Bc6hQuality::High ? 6 : 32;
  try_two_regions(b, n_parts, max_exact, refine_top, passes, perturb, best);
  return best;
}

// Two regions: ranks partitions by how well two lines fit them, tries the `n_parts` best with
// `max_exact` modes each, refines the `refine_top` best of each; keeps the best in `best`.
// `quick` (quality `default`): the cheaper ranking, nothing tried when no partition's two
// lines fit kTwoLineGain times better than one, and the second partition's candidate refined
// only when it is within kRefineSecond of the best so far or of `incumbent_err` (the caller's
// one-region error, when `best` starts empty).
void try_two_regions(const Block& b, int n_parts, int max_exact, int refine_top, int passes, bool perturb,
                     Candidate& best, bool quick, double incumbent_err) {
  std::pair<double, int> ranked[32];
  Moments per_texel[16], all{};
  for (int t = 0; t < 16; ++t) {
    per_texel[t] = texel_moments(b, t);
    all.add(per_texel[t], 1.0);
  }
  if (quick) {
    // Region 1's moments for all 32 partitions from the subset sums of the four rows of texels
    // (4 × 15 sums, then 3 additions per partition instead of one per texel).
    Moments rows[4][16];
    const auto fill_rows = [&] {
      for (int g = 0; g < 4; ++g) {
        rows[g][0] = Moments{};
        for (int m = 1; m < 16; ++m) {
          rows[g][m] = rows[g][m & (m - 1)];
          rows[g][m].add(per_texel[4 * g + std::countr_zero(unsigned(m))], 1.0);
        }
      }
    };
#ifdef __SSE2__
    if (cpu::has(cpu::kSse2)) {
      // The same sums as below (region 1 from the four rows in row order, region 0 as all minus
      // region 1), each component put straight into its lanes (region 0, region 1).
      const double* all_c[10] = {&all.w, &all.s[0], &all.s[1], &all.s[2], &all.ss[0], &all.ss[1], &all.ss[2], &all.ss[3], &all.ss[4], &all.ss[5]};
      double allv[10];
      for (int k = 0; k < 10; ++k) allv[k] = *all_c[k];
      // Lanes {region 0, region 1} of partition p at m[p / 2][k][2·(p & 1)]: all the moments
      // first, then the residuals in one loop (two partitions per AVX2 step, one per SSE2 call),
      // whose steps are independent, so their divisions overlap.
      const bool wide = cpu::has(cpu::kAvx2);
      alignas(32) double m[16][10][4];
      if (wide) {  // the same sums four components per vector (partition_moments_avx2)
        alignas(32) double pt[16][12];
        for (int t = 0; t < 16; ++t) {
          const Moments& q = per_texel[t];
          const double v[12] = {q.w, q.s[0], q.s[1], q.s[2], q.ss[0], q.ss[1], q.ss[2], q.ss[3], q.ss[4], q.ss[5], 0, 0};
          std::memcpy(pt[t], v, sizeof v);
        }
        partition_moments_avx2(pt, allv, kPartitions, m);
      } else {
        fill_rows();
      }
      for (int p = 0; p < 32 && !wide; ++p) {
        const unsigned mask = kPartitions[p];
        const Moments &m0 = rows[0][mask & 15], &m1 = rows[1][(mask >> 4) & 15], &m2 = rows[2][(mask >> 8) & 15],
                      &m3 = rows[3][mask >> 12];
        double (*mp)[4] = m[p / 2];
        const int lane = 2 * (p & 1);
        auto put = [&](int k, double x0, double x1, double x2, double x3) {
          const double r1 = ((x0 + x1) + x2) + x3;
          mp[k][lane] = allv[k] - r1, mp[k][lane + 1] = r1;
        };
        put(0, m0.w, m1.w, m2.w, m3.w);
        for (int i = 0; i < 3; ++i) put(1 + i, m0.s[i], m1.s[i], m2.s[i], m3.s[i]);
        for (int i = 0; i < 6; ++i) put(4 + i, m0.ss[i], m1.ss[i], m2.ss[i], m3.ss[i]);
      }
      double res[32];
      if (wide) {
        pair_residuals_avx2(m, 16, res);
      } else {
        for (int p = 0; p < 32; ++p) {
          __m128d lanes[10];
          for (int k = 0; k < 10; ++k) lanes[k] = _mm_load_pd(&m[p / 2][k][2 * (p & 1)]);
          res[p] = pair_residual_sse2(lanes);
        }
      }
      for (int p = 0; p < 32; ++p) ranked[p] = {res[p], p};
    } else
#endif
    {
      fill_rows();
      for (int p = 0; p < 32; ++p) {
        const unsigned mask = kPartitions[p];
        Moments r1 = rows[0][mask & 15];
        r1.add(rows[1][(mask >> 4) & 15], 1.0);
        r1.add(rows[2][(mask >> 8) & 15], 1.0);
        r1.add(rows[3][mask >> 12], 1.0);
        Moments r0 = all;
        r0.add(r1, -1.0);
        ranked[p] = {line_residual_quick(r0) + line_residual_quick(r1), p};
      }
    }
  } else {
    for (int p = 0; p < 32; ++p) {
      Moments r1{};
      for (int t = 0; t < 16; ++t)
        if ((kPartitions[p] >> t) & 1) r1.add(per_texel[t], 1.0);
      Moments r0 = all;
      r0.add(r1, -1.0);
      ranked[p] = {line_residual(r0) + line_residual(r1), p};
    }
  }
  std::partial_sort(ranked, ranked + n_parts, ranked + 32);
  // Quick: when no two lines fit the block much better than one, two regions (3-bit indices,
  // fewer endpoint bits) rarely beat the one-region incumbent; noise is such a block.
  if (quick && ranked[0].first > kTwoLineGain * line_residual_quick(all)) return;
  for (int i = 0; i < n_parts; ++i) {
    const int p = ranked[i].second;
    double t[2][2][3];
    axis_endpoints_pair(b, kPartitions[p], t);
    Candidate top[2];
    try_modes(b, kTwoRegionOrder, 10, p, t, max_exact, top);
    for (int k = 0; k < 2; ++k) {
      Candidate& c = top[k];
      if (c.mode < 0) continue;
      const double within = quick && i > 0 ? kRefineSecond * std::min(best.err, incumbent_err) : 1e300;
      if (k < refine_top && !(c.err > within)) refine(b, c, passes, perturb);
      if (c.err < best.err) best = c;
    }
  }
}

// ---- Quality `max` (UF16 and SF16) ----
// The search of `high` widened (one region and all 32 partitions, every mode, the two best of
// each refined), then the few best candidates polished on the quantised lattice against the
// exact judged error (polish_max). Candidates are kept only when they lower the error, so `max`
// is never worse than that wide search on any block.

// Moves every endpoint component inside the block's range (Block::comp_lo/comp_hi) and
// re-evaluates: rounding an endpoint just past the no-specks cap loses its palette entries, and
// the descent below cannot always walk back from there. Returns false when nothing moved.
bool move_inside(const Block& b, Candidate& c) {
  const ModeInfo& mi = mode(c.mode);
  bool moved = false;
  for (int k = 0; k < mi.regions * 2; ++k)
    for (int ch = 0; ch < 3; ++ch) {
      const int v = std::clamp(c.e[k][ch], b.comp_lo[mi.epb][ch], b.comp_hi[mi.epb][ch]);
      moved |= v != c.e[k][ch];
      c.e[k][ch] = v;
    }
  if (!moved) return false;
  fit_deltas(mi, c.e, b.is_signed);
  evaluate(b, c);
  fix_anchors(b, c);
  return true;
}

// With the candidate's indices held fixed, the channels of a region's endpoints are independent:
// for each region and channel, every pair of components within ±kWindow of the current pair and
// of the rounded least-squares pair is tried against that channel's exact error, with every entry
// the texels use kept inside the block's range (no specks); the best pair is kept. Then the
// indices are chosen again. Returns true when the candidate's error dropped.
constexpr int kWindow = 4;
bool improve_channels(const Block& b, Candidate& cand) {
  const ModeInfo& mi = mode(cand.mode);
  const uint16_t mask = mi.regions == 2 ? kPartitions[cand.partition] : 0;
  const uint8_t* weights = mi.index_bits == 3 ? kWeights3 : kWeights4;
  const float* L = log_table();
  const int maxv = b.is_signed ? (1 << (mi.epb - 1)) - 1 : (1 << mi.epb) - 1, minv = b.is_signed ? -maxv : 0;
  const double lim = b.is_signed ? 0x7FFF : 0xFFFF, low = b.is_signed ? -0x7FFF : 0;
  Candidate c = cand;
  for (int r = 0; r < mi.regions; ++r) {
    double lo[3], hi[3];
    const bool have_ls = refit_region(b, cand, r, lo, hi);
    int texels[16], n = 0;
    for (int t = 0; t < 16; ++t)
      if (int((mask >> t) & 1) == r && b.valid[t] > 0) texels[n++] = t;
    for (int ch = 0; ch < 3; ++ch) {
      auto channel_err = [&](int qa, int qb, double bound) {
        const int ua = unquantize(qa, mi.epb, b.is_signed), ub = unquantize(qb, mi.epb, b.is_signed);
        double e = 0;
        for (int i = 0; i < n && e < bound; ++i) {
          const int t = texels[i];
          const int h = decoded_h(interpolate(ua, ub, weights[c.idx[t]]), b.is_signed);
          if (h > b.cap[ch] || h < b.floor_[ch]) return 1e300;
          const double d = L[half_bits_of(h)] - b.L[t][ch];
          e += d * d;
        }
        return e;
      };
      auto deltas_fit = [&](int qa, int qb) {
        if (!mi.transformed) return true;
        const int dlo = -(1 << (mi.delta[ch] - 1)), dhi = (1 << (mi.delta[ch] - 1)) - 1;
        const int e0 = r == 0 ? qa : c.e[0][ch];
        for (int k = 1; k < mi.regions * 2; ++k) {
          const int v = k == r * 2 ? qa : k == r * 2 + 1 ? qb : c.e[k][ch];
          if (v - e0 < dlo || v - e0 > dhi) return false;
        }
        return true;
      };
      int best_a = c.e[r * 2][ch], best_b = c.e[r * 2 + 1][ch];
      double best = channel_err(best_a, best_b, 1e300);
      int centers[2][2] = {{best_a, best_b}, {best_a, best_b}};
      if (have_ls) {
        centers[1][0] = quantize(std::clamp(lo[ch], low, lim), mi.epb, b.is_signed);
        centers[1][1] = quantize(std::clamp(hi[ch], low, lim), mi.epb, b.is_signed);
      }
      // 6-bit endpoints (mode 10, the only two-region mode for a black and a lit region): all
      // 64² pairs, since the palette's spacing there is coarser than the texels' spread and the
      // entry the texels need may come from any pair.
      const int window = mi.epb <= 6 ? maxv - minv : kWindow;
      const int n_centers = mi.epb <= 6 ? 1 : have_ls ? 2 : 1;
      for (int k = 0; k < n_centers; ++k)
        for (int qa = std::max(minv, centers[k][0] - window); qa <= std::min(maxv, centers[k][0] + window); ++qa)
          for (int qb = std::max(minv, centers[k][1] - window); qb <= std::min(maxv, centers[k][1] + window); ++qb) {
            if (!deltas_fit(qa, qb)) continue;
            const double e = channel_err(qa, qb, best);
            if (e < best) best = e, best_a = qa, best_b = qb;
          }
      c.e[r * 2][ch] = best_a, c.e[r * 2 + 1][ch] = best_b;
    }
  }
  if (!fit_deltas(mi, c.e, b.is_signed)) return false;
  evaluate(b, c);
  fix_anchors(b, c);
  if (!(c.err < cand.err)) return false;
  cand = c;
  return true;
}

// Coordinate descent on the quantised endpoints: each component in turn moves by ±step for
// step = kMaxStep … 1 (a logarithmic line search), keeping a move when the exact error drops;
// then least squares on the new indices (re-quantised, and moved inside the range). Rounds
// repeat until one does not lower the error. Moves that break a mode's deltas are not taken.
constexpr int kMaxStep = 16, kMaxRounds = 8;
void polish_max(const Block& b, Candidate& best) {
  const ModeInfo& mi = mode(best.mode);
  const int maxv = b.is_signed ? (1 << (mi.epb - 1)) - 1 : (1 << mi.epb) - 1, minv = b.is_signed ? -maxv : 0;
  for (int round = 0; round < kMaxRounds && best.err > 0; ++round) {
    const double before = best.err;
    for (int k = 0; k < mi.regions * 2; ++k)
      for (int ch = 0; ch < 3; ++ch)
        for (int step = kMaxStep; step >= 1; step >>= 1) {
          Candidate moved = best;
          for (int d : {-step, step}) {
            Candidate c = best;
            c.e[k][ch] += d;
            if (c.e[k][ch] < minv || c.e[k][ch] > maxv || !fit_deltas(mi, c.e, b.is_signed)) continue;
            evaluate(b, c);
            fix_anchors(b, c);
            if (c.err < moved.err) moved = c;
          }
          if (moved.err < best.err) best = moved;
        }
    for (int it = 0; it < 4 && improve_channels(b, best); ++it) {
    }
    refine(b, best, 2, false);
    Candidate inside = best;
    if (move_inside(b, inside) && inside.err < best.err) best = inside;
    if (!(best.err < before)) break;
  }
}

constexpr int kMaxPolished = 4;  // candidates polished per block

Candidate search_max(const Block& b) {
  Candidate best = in_range_candidate(b);
  Candidate pool[2 + 32 * 2];
  int n = 0;
  auto add = [&](const Candidate top[2]) {
    for (int k = 0; k < 2; ++k) {
      if (top[k].mode < 0) continue;
      Candidate c = top[k];
      refine(b, c, 6, /*perturb=*/true);
      pool[n++] = c;
    }
  };
  {
    double t[2][2][3];
    axis_endpoints(b, 0, 0, t[0][0], t[0][1]);
    Candidate top[2];
    try_modes(b, kOneRegionOrder, 4, 0, t, /*max_exact=*/0, top);
    add(top);
  }
  for (int i = 0; i < n; ++i)
    if (pool[i].err < best.err) best = pool[i];
  if (best.err <= 0) return best;  // exact in one region (many smooth blocks, in mode 14)
  for (int p = 0; p < 32; ++p) {
    double t[2][2][3];
    axis_endpoints_pair(b, kPartitions[p], t);
    Candidate top[2];
    try_modes(b, kTwoRegionOrder, 10, p, t, /*max_exact=*/0, top);
    add(top);
  }
  // The best first; ties by the order found (stable), so the bytes depend on the block only.
  std::stable_sort(pool, pool + n, [](const Candidate& x, const Candidate& y) { return x.err < y.err; });
  for (int i = 0; i < n; ++i)
    if (pool[i].err < best.err) best = pool[i];
  for (int i = 0; i < std::min(n, kMaxPolished) && best.err > 0; ++i) {
    if (!(pool[i].err < 1e300)) break;
    Candidate starts[2] = {pool[i], pool[i]};
    const bool second = move_inside(b, starts[1]);
    for (int s = 0; s < (second ? 2 : 1); ++s) {
      if (!(starts[s].err < 1e300)) continue;
      polish_max(b, starts[s]);
      if (starts[s].err < best.err) best = starts[s];
    }
  }
  return best;
}

}  // namespace

bool bc6h_quality_from_name(const std::string& name, Bc6hQuality* out) { return parse_enum(kBc6hQualities, name, out); }

const char* bc6h_quality_name(Bc6hQuality q) { return enum_name(kBc6hQualities, q); }

namespace {

// The input rule (NaN → 0, ±Inf and |x| > 65504 → ±65504, negatives → 0 in UF16), counting what
// it changed in `counts` (nan, inf, too large, negative) when given.
inline float apply_input_rule(float v, bool is_signed, size_t* counts) {
  constexpr float kMax = 65504.0f;
  if (!(std::fabs(v) <= kMax)) {  // NaN, ±Inf or beyond half's range: the rare path
    if (std::isnan(v)) {
      if (counts) counts[0]++;
      v = 0.0f;
    } else {
      if (counts) counts[std::isinf(v) ? 1 : 2]++;
      v = std::copysign(kMax, v);
    }
  }
  if (!is_signed && v < 0.0f) {
    if (counts) counts[3]++;
    v = 0.0f;
  }
  return v;
}

// The search's view of a block of ruled values.
// `half`, when given, holds the values' half bits (UF16: the fast fit's conversion, reused).
// The search's targets of a block of ruled values: half bits, the metric's targets, the range.
// `half`, when given, holds the values' half bits (UF16: the fast fit's conversion, reused).
void fill_targets(const float rgb[48], const uint8_t valid[16], bool is_signed, Block& b, const uint16_t* half = nullptr) {
  b.is_signed = is_signed;
  const float* L = log_table();
  for (int t = 0; t < 16; ++t) {
    b.valid[t] = valid[t] ? 1.0f : 0.0f;
    for (int c = 0; c < 3; ++c) {
      b.h[t][c] = half ? int(half[t * 3 + c]) : half_signed_int(rgb[t * 3 + c]);
      b.L[t][c] = b.Lp[c][t] = L[half_bits_of(b.h[t][c])];
    }
  }

  // No decoded value may exceed its channel's brightest input in the block by more than one
  // half-float step (nor, signed, go below its darkest by more than one step): no specks.
  // Padding texels take values that change neither extreme (selects, not branches).
  for (int c = 0; c < 3; ++c) {
    int cap = -(1 << 30), floor = 1 << 30;
    for (int t = 0; t < 16; ++t) {
      const int v = b.h[t][c];
      cap = std::max(cap, valid[t] ? v : -(1 << 30));
      floor = std::min(floor, valid[t] ? v : 1 << 30);
    }
    b.cap[c] = cap + 1;
    b.floor_[c] = is_signed ? floor - 1 : -(1 << 30);
  }
}

// The search's geometry (after fill_targets): c-domain values and least-squares weights, which
// the principal axes, the partition ranking and the least squares use.
void fill_geometry(const float rgb[48], const uint8_t valid[16], Block& b) {
  for (int t = 0; t < 16; ++t) {
    double tw = 0;
    for (int c = 0; c < 3; ++c) {
      const float v = rgb[t * 3 + c];
      b.q[t][c] = b.is_signed ? b.h[t][c] * 32.0 / 31.0 : b.h[t][c] * 64.0 / 31.0;
      // Geometry weight: the slope of log2(1+x) per half step, floored at x = 0.25 so that dark
      // texels still pull the endpoints (their errors are large ones, where the slope lies).
      const double x = std::max(double(std::fabs(v)), 0.25);
      b.w[t][c] = valid[t] ? (x / (1 + x)) * (x / (1 + x)) : 0.0;
      tw += b.w[t][c];
    }
    b.tw[t] = valid[t] ? tw / 3 + 1e-12 : 0.0;
  }
}

void encode_block_default(const uint16_t h[48], const float rgb[48], const uint8_t valid[16], OneRegionFit fit,
                          uint8_t out[16]);

// The judged error of an encoded UF16 block: Σ over valid texels and channels of
// (log2(1 + decoded) − log2(1 + target))², the metric the candidates' err holds.
double judged_error_uf16(const Block& b, const uint8_t block[16]) {
  uint16_t dec[48];
  bc6h_decode_block(block, false, dec);
  const float* L = log_table();
  double e = 0;
  for (int t = 0; t < 16; ++t)
    for (int c = 0; c < 3; ++c) {
      const double d = double(L[dec[t * 3 + c]]) - double(b.L[t][c]);
      e += b.valid[t] * d * d;
    }
  return e;
}

void encode_block_searched(const float rgb[48], const uint8_t valid[16], bool is_signed, Bc6hQuality q, uint8_t out[16]) {
  Block b;
  fill_targets(rgb, valid, is_signed, b);
  fill_geometry(rgb, valid, b);
  if (q == Bc6hQuality::Max) {
    for (int bits = 6; bits <= 16; ++bits)
      for (int c = 0; c < 3; ++c) {
        b.comp_hi[bits][c] = quantize_capped(b.cap[c], bits, is_signed, /*floor=*/false);
        b.comp_lo[bits][c] = std::min(b.comp_hi[bits][c], quantize_capped(b.floor_[c], bits, is_signed, /*floor=*/true));
      }
  }
  Candidate best = q == Bc6hQuality::Max ? search_max(b) : search(b, q);
  pack(best, is_signed, out);
  if (q == Bc6hQuality::Max && !is_signed && best.err > 0) {
    // Issue 28: `max` lowest on every image. `default`'s polished fast fit beat max's search on
    // noisy blocks (noisy image: default 0.04573, max 0.04639), so max also encodes the block as
    // default does and keeps whichever decodes closer in the judged metric (ties: max's own).
    uint16_t h[48];
    floats_to_half(rgb, h, 48);
    OneRegionFit fit;
    fit_one_region_fast(h, rgb, valid, &fit);
    uint8_t alt[16];
    encode_block_default(h, rgb, valid, fit, alt);
    if (judged_error_uf16(b, alt) < judged_error_uf16(b, out)) std::memcpy(out, alt, 16);
  }
}

// Quality `default`'s cheap bound before the partition ranking: true when the block's texels lie
// near one line but not on it — the off-line share of their weighted variance (half-bit domain,
// the geometry weights of fill_geometry) within [kNoiseBand[0], kNoiseBand[1]). That is noise
// along the line, which no partition's two lines explain (on ../shared/data/bc6h no such block
// gained from two regions on the noisy or hard image). Float, centred, plain loops (vectorised).
bool noise_along_one_line(const float rgb[48], const Block& b) {
  float tw[16], q[3][16];
  for (int t = 0; t < 16; ++t) {
    float sum = 0;
    for (int c = 0; c < 3; ++c) {
      const float x = std::max(rgb[t * 3 + c], 0.25f), s = x / (1.0f + x);
      sum += s * s;
      q[c][t] = float(b.h[t][c]);
    }
    tw[t] = b.valid[t] * sum;
  }
  float w = 0, m[3] = {0, 0, 0};
  for (int t = 0; t < 16; ++t) w += tw[t];
  for (int c = 0; c < 3; ++c) {
    for (int t = 0; t < 16; ++t) m[c] += tw[t] * q[c][t];
    m[c] /= w;
    for (int t = 0; t < 16; ++t) q[c][t] -= m[c];
  }
  float xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
  for (int t = 0; t < 16; ++t) {
    xx += tw[t] * q[0][t] * q[0][t], yy += tw[t] * q[1][t] * q[1][t], zz += tw[t] * q[2][t] * q[2][t];
    xy += tw[t] * q[0][t] * q[1][t], xz += tw[t] * q[0][t] * q[2][t], yz += tw[t] * q[1][t] * q[2][t];
  }
  const float trace = xx + yy + zz;
  if (!(trace > 0)) return false;
  // Two power steps from the column of largest variance, then the Rayleigh quotient (as
  // line_residual_quick), scaled by 1/trace so that float cannot overflow.
  float v[3] = {xx, xy, xz};
  if (yy > xx && yy >= zz) v[0] = xy, v[1] = yy, v[2] = yz;
  else if (zz > xx && zz > yy) v[0] = xz, v[1] = yz, v[2] = zz;
  const float inv = 1.0f / trace;
  for (int it = 0; it < 2; ++it) {
    const float u0 = (xx * v[0] + xy * v[1] + xz * v[2]) * inv, u1 = (xy * v[0] + yy * v[1] + yz * v[2]) * inv,
                u2 = (xz * v[0] + yz * v[1] + zz * v[2]) * inv;
    v[0] = u0, v[1] = u1, v[2] = u2;
  }
  const float vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (!(vv > 0)) return false;
  const float lambda = (v[0] * (xx * v[0] + xy * v[1] + xz * v[2]) + v[1] * (xy * v[0] + yy * v[1] + yz * v[2]) +
                        v[2] * (xz * v[0] + yz * v[1] + zz * v[2])) / vv;
  const float off_line = trace - lambda;
  return off_line >= float(kNoiseBand[0]) * trace && off_line < float(kNoiseBand[1]) * trace;
}

// The scale of `default`'s two-region gates for a block (kDarkRef): min(1, (s/kDarkRef)²), s the
// mean of x/(1+x) over the valid texels' channels (x ≥ 0, the input rule applied).
double dark_gate_scale(const float rgb[48], const uint8_t valid[16]) {
  float sum = 0, n = 0;
  for (int t = 0; t < 16; ++t)
    for (int c = 0; c < 3; ++c) {
      const float x = rgb[t * 3 + c];
      sum += valid[t] ? x / (1.0f + x) : 0.0f;
      n += valid[t] ? 1.0f : 0.0f;
    }
  const double s = double(sum) / double(n);
  return std::min(1.0, s * s / (kDarkRef * kDarkRef));
}

// Quality `default`, UF16: the real-time one-region fit (bc6h_fast.cpp) is the incumbent, and
// the search runs only where it can pay:
//  * a block whose fit error is at most kFastGood (weighted squared half steps, the fast path's
//    own measure) is written as the fast path writes it;
//  * otherwise the incumbent's indices are re-picked in the judged metric (every palette entry per
//    texel) and its quantised endpoints polished with those indices held (polish_steps: ±1 steps,
//    one palette lookup per index group);
//  * only if its error is still above kTwoRegionWorth, and the block is not noise along one line
//    (noise_along_one_line, for errors below kNoiseErr), both gates scaled down for dark blocks
//    (dark_gate_scale), are the polished endpoints' indices
//    re-picked, the kPartitionsTried best-ranked partitions tried in their most precise mode
//    whose deltas fit, each refined kTwoRegionPasses times (unless no partition's two lines fit
//    the block kTwoLineGain times better than one line; the second one only within
//    kRefineSecond of the best), the incumbent refined by least squares (kOneRegionPasses)
//    unless two regions beat it kTwoRegionsClear times over, and the winner polished again
//    unless it is the polished incumbent unchanged.
// The constants were chosen on ../shared/data/bc6h (smooth / hard / noisy; callgrind instruction
// counts and log-RMSE, issue 13). Measured alternatives: without the polish 0.00855 / 0.00794 /
// 0.04617 (the polish gives 0.00827 / 0.00794 / 0.04580 and pays for the pruning below); the
// 32-partition ranking on every block cost the noisy image 216 M of 679 M instructions for 98
// winning blocks, none in the noise band; noise band up to 1/512 instead of 1/256: noisy +11 M
// instructions, same error; the indices re-picked after the polish on every block: noisy
// +50 M, 0.04572; the polish from the fast fit's own indices (no first re-pick): hard 0.00803,
// noisy 0.04590; no least squares in the two-region branch: hard 0.00797. Earlier ones:
// kTwoLineGain 0.25 cost hard +7 % log-RMSE, 0.20 +22 %; kFastGood 10 000 +2 %; one partition
// instead of two +3 % on smooth; a noise test of texels far from any one line saved nothing on
// the noisy image (its noise lies along the grey line: off-line shares of 2^-13..2^-8) and cost
// hard +4 %.
// `fit` is the block's fit_one_region_fast (images take it from fit_blocks_fast, eight blocks per
// AVX2 batch; the same fit bit for bit).
void encode_block_default(const uint16_t h[48], const float rgb[48], const uint8_t valid[16], OneRegionFit fit,
                          uint8_t out[16]) {
  if (fit.err <= kFastGood) {
    pack_one_region(fit, out);
    return;
  }
  const OneRegionFit fast_fit = fit;
  Block b;
  fill_targets(rgb, valid, false, b, h);
  Candidate best;
  best.mode = fit.mode;
  std::memcpy(best.e, fit.e, sizeof fit.e);
  evaluate(b, best);  // inside the block's range by construction: never rejected
  fix_anchors(b, best);
  if (best.err >= 1e300) best = in_range_candidate(b);  // defensive: the bound holds regardless
  // Polished with the indices held; the error follows from the per-channel gains.
  Candidate held = best;
  double gain = 0;
  const bool moved = polish_steps(b, held, kPolishRounds, &gain);
  held.err -= gain;
  best = held;
  const double dark = dark_gate_scale(rgb, valid);
  if (held.err > kTwoRegionWorth * dark && !(held.err < kNoiseErr * dark && noise_along_one_line(rgb, b))) {
    // A block that may need two regions: the polished endpoints' indices re-picked first.
    if (moved) {
      Candidate c = held;
      evaluate(b, c);
      fix_anchors(b, c);
      if (c.err < best.err) best = c;
    }
    fill_geometry(rgb, valid, b);
    // Two regions first: when they beat the incumbent clearly, its refinement cannot change the
    // winner often enough to pay (kTwoRegionsClear).
    Candidate two;
    try_two_regions(b, kPartitionsTried, /*max_exact=*/1, /*refine_top=*/1, kTwoRegionPasses, false, two, true, best.err);
    if (!(two.err < kTwoRegionsClear * best.err)) refine(b, best, kOneRegionPasses, false);
    if (two.err < best.err) best = two;
    // The winner still the polished incumbent with its held indices: it was polished above
    // already (a second polish moves it only where the first ran out of rounds; hard's error
    // unchanged to 7 digits, 1.3 M instructions fewer).
    const bool still_held = best.mode == held.mode && best.err == held.err &&
                            std::memcmp(best.e, held.e, sizeof best.e) == 0 && std::memcmp(best.idx, held.idx, sizeof best.idx) == 0;
    if (!still_held) polish(b, best, kPolishRounds);
  }
  if (best.mode < 10) {
    pack(best, false, out);
  } else {
    fit.mode = best.mode;  // one region: the fast path's packing (anchor already fixed)
    std::memcpy(fit.e, best.e, sizeof fit.e);
    std::memcpy(fit.idx, best.idx, sizeof fit.idx);
    pack_one_region(fit, out);
  }
  // Issue 45: `fast`'s two-region candidate (bc6h_fast_two_region.cpp: eight ranked partitions,
  // or the brightness split on edge blocks) is not among the candidates above, whose two-region
  // search is gated (kTwoRegionWorth, the noise band, kTwoLineGain) and tries kPartitionsTried
  // partitions. On the path-traced bakes' I_z (docs/bc6h-real.md) that lost it on the blocks
  // where it wins, and `default` came out less accurate than `fast` (lamps 0.05481 against
  // 0.04572). So the block `fast` writes is a candidate too, kept when it decodes closer in the
  // judged metric (ties: the search's own): `default` is never worse than `fast` on a block.
  uint8_t alt[16];
  pack_one_region(fast_fit, alt);
  if (improve_with_two_regions(h, rgb, valid, fast_fit.err, alt) && judged_error_uf16(b, alt) < judged_error_uf16(b, out))
    std::memcpy(out, alt, 16);
}

// A block whose values already follow the input rule: `fast` UF16 takes the real-time path
// (bc6h_fast.cpp), everything else the search.
void encode_block_ruled(const float rgb[48], const uint8_t valid[16], bool is_signed, Bc6hQuality q, uint8_t out[16]) {
  if (q == Bc6hQuality::Fast && !is_signed) {
    uint16_t h[48];
    floats_to_half(rgb, h, 48);
    encode_blocks_fast(h, rgb, valid, 1, out);
    return;
  }
  if (q == Bc6hQuality::Default && !is_signed) {
    uint16_t h[48];
    floats_to_half(rgb, h, 48);
    OneRegionFit fit;
    fit_one_region_fast(h, rgb, valid, &fit);
    encode_block_default(h, rgb, valid, fit, out);
    return;
  }
  encode_block_searched(rgb, valid, is_signed, q, out);
}

}  // namespace

void bc6h_encode_block(const float rgb[48], const uint8_t valid[16], bool is_signed, Bc6hQuality q, uint8_t out[16]) {
  float ruled[48];
  for (int i = 0; i < 48; ++i) ruled[i] = apply_input_rule(rgb[i], is_signed, nullptr);
  encode_block_ruled(ruled, valid, is_signed, q, out);
}


std::vector<uint8_t> bc6h_encode_image(const ImageF& img, const Bc6hOptions& opt, Bc6hStats* stats) {
  const int bw = (img.width + 3) / 4, bh = (img.height + 3) / 4;
  std::vector<uint8_t> out(size_t(bw) * bh * 16);
  // The input rule is applied as each block is gathered (no copy of the image: at real-time
  // speeds a copy costs as much as the encoding); counts are summed, so they do not depend on
  // the thread count either.
  std::atomic<size_t> counts[4] = {0, 0, 0, 0};  // nan, inf, too large, negative
  const size_t blocks = size_t(bw) * bh;
  // Gathers block blk with the input rule applied, counting what it changed.
  const auto gather = [&](size_t blk, float rgb[48], uint8_t valid[16]) {
    const int bx = int(blk % bw), by = int(blk / bw);
    size_t local[4] = {0, 0, 0, 0};
    for (int t = 0; t < 16; ++t) {
      const int x = bx * 4 + t % 4, y = by * 4 + t / 4;
      valid[t] = x < img.width && y < img.height;
      const float* p = img.at(std::min(x, img.width - 1), std::min(y, img.height - 1));
      for (int c = 0; c < 3; ++c) {
        const float v = c < img.channels ? p[c] : 0.0f;
        rgb[t * 3 + c] = apply_input_rule(v, opt.is_signed, valid[t] ? local : nullptr);
      }
    }
    for (int i = 0; i < 4; ++i)
      if (local[i]) counts[i].fetch_add(local[i], std::memory_order_relaxed);
  };
  if ((opt.quality == Bc6hQuality::Fast || opt.quality == Bc6hQuality::Default) && !opt.is_signed) {
    // The one-region fits of `fast` and of `default`'s incumbents, 128 blocks per call (eight
    // AVX-512 batches or sixteen AVX2 ones; bc6h_fast.cpp); `default` then searches the blocks
    // that need it one by one.
    constexpr size_t kBatch = 128;
    parallel_for((blocks + kBatch - 1) / kBatch, opt.threads, 2, [&](size_t g) {
      const int n = int(std::min(kBatch, blocks - g * kBatch));
      float rgb[kBatch][48];
      uint16_t h[kBatch][48];
      uint8_t valid[kBatch][16];
      // A block equal bit for bit to the one gathered before it (gutters, flat areas, dark
      // corners of real lightmaps) is not encoded again: it takes that block's bytes. Each
      // block's encoding depends only on its own values (the contracts of encode_blocks_fast and
      // encode_block_default), so the bytes are those of encoding it anew; groups are fixed, so
      // they do not depend on the thread count either. Block i's bytes are unique block slot[i]'s.
      int slot[kBatch];
      int u = 0;  // unique blocks gathered: rgb[0..u), valid[0..u)
      for (int i = 0; i < n; ++i) {
        const size_t blk = g * kBatch + size_t(i);
        const int bx = int(blk % bw), by = int(blk / bw);
        // Inner blocks of 3-channel images whose values the input rule leaves alone: one copy.
        if (img.channels == 3 && bx * 4 + 4 <= img.width && by * 4 + 4 <= img.height &&
            copy_block_in_range(img.at(bx * 4, by * 4), size_t(img.width) * 3, rgb[u]))
          std::memset(valid[u], 1, 16);
        else gather(blk, rgb[u], valid[u]);
        const bool repeat = u > 0 && std::memcmp(rgb[u], rgb[u - 1], sizeof rgb[0]) == 0 &&
                            std::memcmp(valid[u], valid[u - 1], sizeof valid[0]) == 0;
        slot[i] = repeat ? u - 1 : u++;
      }
      uint8_t* const dst = &out[g * kBatch * 16];
      uint8_t unique_out[kBatch * 16];
      uint8_t* const enc = u == n ? dst : unique_out;  // no repeats: straight into the image
      // Each of the u blocks was written above (copied or gathered); GCC 12 cannot see it through
      // the loop and warns that the const pointer may read uninitialised floats.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
      floats_to_half(rgb[0], h[0], 48 * u);
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
      if (opt.quality == Bc6hQuality::Fast) {
        encode_blocks_fast(h[0], rgb[0], valid[0], u, enc);
      } else {
        OneRegionFit fits[kBatch];
        fit_blocks_fast(h[0], rgb[0], valid[0], u, fits);
        for (int i = 0; i < u; ++i) encode_block_default(h[i], rgb[i], valid[i], fits[i], &enc[size_t(i) * 16]);
      }
      if (enc != dst)
        for (int i = 0; i < n; ++i) std::memcpy(&dst[size_t(i) * 16], &enc[size_t(slot[i]) * 16], 16);
    });
  } else {
    parallel_for(blocks, opt.threads, 16, [&](size_t blk) {
      float rgb[48];
      uint8_t valid[16];
      gather(blk, rgb, valid);
      encode_block_ruled(rgb, valid, opt.is_signed, opt.quality, &out[blk * 16]);
    });
  }
  if (stats) {
    stats->nan = counts[0].load(), stats->inf = counts[1].load();
    stats->too_large = counts[2].load(), stats->negative = counts[3].load();
  }
  return out;
}

}  // namespace ahd

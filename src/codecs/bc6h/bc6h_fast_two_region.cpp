// BC6H `fast`: the two-region candidate, for the blocks one region fits poorly.
//
// The one-region fit (bc6h_fast.cpp) cannot follow a block with two clusters of colour, and on
// noisy lightmaps no amount of least squares on one region gets below the real-time peers (Basis
// Universal's real-time encoder tries 2-subset patterns, facts only). This candidate stays in the
// fast path's style: float arithmetic on half bits weighted by the metric's slope, the partition
// chosen by a cheap ranking (how well two lines fit its two regions, from moment sums), endpoints
// from each region's principal axis, indices by projection, one least-squares pass. It runs only
// for blocks whose one-region error is above kGate (so smooth and hard blocks, nearly all below,
// keep their speed), and replaces the one-region block only when its error is lower, in the same
// measure. Plain C++, one block at a time: the bytes depend only on the block and on the
// one-region error, which every path of encode_blocks_fast computes identically.
//
// No specks: every endpoint is quantised so that it decodes at most one half step above its
// channel's brightest input (as the one-region fit), and palette entries lie between endpoints.
#include <bit>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <cstdio>
#include <cstdlib>

#include "codecs/bc6h/bc6h_fast.h"
#include "codecs/bc6h/bc6h_tables.h"

#include "codecs/bc6h/bc6h_two_region.h"
#include "core/cpu.h"

namespace ahd::bc6h {

namespace {

using namespace two_region;

// One-region error (weighted squared half steps) above which the candidate is tried; partitions
// fitted from their axes (best-ranked first); how many of the best of those get least-squares
// passes, and how many passes. Chosen on ../shared/data/bc6h (fast, log-RMSE smooth / hard /
// noisy). With the gate at 3000 (15 % / 23 % / 100 % of the blocks), one partition, one pass:
// 0.00951 / 0.00851 / 0.04636 at 3.6 MPix/s on noisy. Nearly all of the gain on noisy and smooth
// comes from blocks above 3·10⁵ (0.3 % / 0.0 % / 2.3 % of the blocks; 95 % of noisy's gain):
// below it a lightmap's noise lies along one line, and two regions (3-bit indices) rarely win.
// Noisy, every tried partition refined: gate 2.5·10⁵, 8 partitions 0.04629, 16 0.04627 (half the
// speed); gate 3·10⁵, 8 0.04631, 32 0.04628; gate 10⁵, 4 partitions one pass 0.04630 at 4.7 MPix/s.
// Refining only the 2 best of 8: 0.04630 at about 1.4× the speed (16 partitions: 0.04629).
constexpr float kGate = 2.5e5f;
constexpr int kTried = 8, kRefined = 2, kPasses = 2;

// Issue 45, the path-traced bakes (docs/bc6h-real.md "A wider real corpus: the path-traced
// bakes' I_z"): on their small, noisy blocks nearly every block passed kGate and the search above
// cost 2.5 µs a block (lamps_256: 7 MPix/s against Basis HQ's 27). A gated block now takes one of
// four routes (route()):
//  * Edge: a texel kEdge times darker than the brightest (a black gutter, a lamp's rim): the
//    brightness split decides the regions, so the partition whose mask is nearest to it (Hamming
//    distance) is the only one tried, with kEdgeRefined least-squares passes; no ranking.
//  * Skip, colour noise: the texels do not lie near one line (the share of the weighted variance
//    off the principal axis above kColourNoise), the one-region fit leaves more than
//    1/kExplained of the variance, and a split along the principal axis puts less than kClusters
//    of it between the halves (not two clusters of different colour, which two regions fit):
//    two lines with 3-bit indices cannot follow noise in three directions either, and gained
//    least there (best/one-region error 0.47–0.78 on lamps_256, against 0.33–0.54 on
//    lightmap_noisy's colour-noise blocks, which kExplained keeps: variance/error 8.4–15 there,
//    3.6–10.5 on lamps_256).
//  * Narrow, the other colour-noise blocks: the kNarrowTried best-ranked partitions,
//    kNarrowRefined of them refined.
//  * Search, the rest (texels near one line, or two clusters): the eight partitions as before.
// Measured on the 14-image corpus (fast, log-RMSE; MPix/s in the commit and the doc):
// lightmap_noisy 0.04630 → 0.04632 (Basis HQ 0.04633), lamps_256 0.06897 → 0.07910 (0.08810),
// emissive 0.05179 → 0.05316 (0.06460). Tried: colour noise from 1/16 (lamps_256 28.5 instead
// of 29.7 MPix/s, same errors); three narrow partitions (lamps_256 26.8, noisy unchanged);
// kExplained 9 (noisy 0.04634, above HQ).
constexpr float kColourNoise = 1.0f / 32, kExplained = 8.0f, kEdge = 64.0f, kClusters = 0.75f;
constexpr int kEdgeRefined = 1, kNarrowTried = 2, kNarrowRefined = 1;

// Two-region modes (0-based) by endpoint precision, most precise first; the last has absolute
// endpoints and always fits.
constexpr int kOrder[10] = {2, 3, 4, 0, 5, 6, 7, 8, 1, 9};

// The component (bits wide) decoding nearest `target` (half bits) without exceeding `cap`.
int quantize_capped(float target, int bits, int cap) {
  const int maxv = (1 << bits) - 1;
  int e = std::clamp(int(target * (64.0f / 31.0f) * float(1 << bits) * (1.0f / 65536.0f)), 0, maxv);
  if (e < maxv && std::fabs(float(dec(unq(e + 1, bits))) - target) < std::fabs(float(dec(unq(e, bits))) - target)) ++e;
  while (e > 0 && dec(unq(e, bits)) > cap) --e;
  return e;
}

// The palette entry whose weight is at or below p, for p = 0..64.
struct Below {
  uint8_t k[65];
  constexpr Below() : k{} {
    for (int p = 0; p <= 64; ++p) {
      int j = 0;
      while (j < 7 && kW3[j + 1] <= p) ++j;
      k[p] = uint8_t(j);
    }
  }
};
constexpr Below kBelow;

// Palette of one region (decoded half bits as floats), 8 entries per channel.
void palette(const int a[3], const int b[3], int bits, float P[3][8]) {
  for (int c = 0; c < 3; ++c) {
    const int ua = unq(a[c], bits), ub = unq(b[c], bits);
    for (int k = 0; k < 8; ++k) P[c][k] = float(dec(interpolate(ua, ub, kWeights3[k])));
  }
}

// Indices of one region's texels (projection on the palette's segment, then the better
// neighbour); returns their weighted squared error.
float assign_region(const Planes& f, uint16_t mask, int r, const int a[3], const int b[3], int bits, uint8_t idx[16]) {
  float P[3][8];
  palette(a, b, bits, P);
  const float d0 = P[0][7] - P[0][0], d1 = P[1][7] - P[1][0], d2 = P[2][7] - P[2][0];
  int list[16], n = 0;  // the region's texels in order, without a branch per texel
  for (int t = 0; t < 16; ++t) list[n] = t, n += int((mask >> t) & 1) == r;
  float total = 0;
  for (int i = 0; i < n; ++i) {
    const int t = list[i];
    const float w0 = f.W[0][t], w1 = f.W[1][t], w2 = f.W[2][t];
    const float num = w0 * d0 * (f.H[0][t] - P[0][0]) + w1 * d1 * (f.H[1][t] - P[1][0]) + w2 * d2 * (f.H[2][t] - P[2][0]);
    const float den = w0 * d0 * d0 + w1 * d1 * d1 + w2 * d2 * d2;
    const float p = std::clamp(64.0f * num / (den > 0 ? den : 1.0f), 0.0f, 64.0f);  // weight units
    const int k = kBelow.k[int(p)];  // the entry at or below p, then the better of it and the next
    auto err = [&](int j) {
      const float e0 = P[0][j] - f.H[0][t], e1 = P[1][j] - f.H[1][t], e2 = P[2][j] - f.H[2][t];
      return w0 * e0 * e0 + w1 * e1 * e1 + w2 * e2 * e2;
    };
    float best = err(k);
    int kb = k;
    if (k < 7) {
      const float e = err(k + 1);
      if (e < best) best = e, kb = k + 1;
    }
    idx[t] = uint8_t(kb);
    total += best;
  }
  return total;
}

// Least squares for one region's endpoints given its indices (half bits), held under the cap as
// the one-region refit does. Returns false when a channel's system is singular.
bool refit_region(const Planes& f, uint16_t mask, int r, const uint8_t idx[16], float a[3], float b[3]) {
  for (int c = 0; c < 3; ++c) {
    float s00 = 0, s01 = 0, s11 = 0, t0 = 0, t1 = 0;
    for (int t = 0; t < 16; ++t) {
      if (int((mask >> t) & 1) != r) continue;
      const float g = float(kWeights3[idx[t]]) * (1.0f / 64.0f), w = f.W[c][t], wa = w * (1 - g), wb = w * g;
      s00 += wa * (1 - g), s01 += wa * g, s11 += wb * g, t0 += wa * f.H[c][t], t1 += wb * f.H[c][t];
    }
    if (!solve_endpoints_held_cap(s00, s01, s11, t0, t1, float(f.cap[c]), &a[c], &b[c])) return false;
  }
  return true;
}

// Weighted moments of a set of texels (centred half bits): w, Σw·x, Σw·x·xᵀ (xx yy zz xy xz yz).
struct Mom {
  float v[10];
};

// trace − principal eigenvalue of the covariance of each of n regions (two power steps, Rayleigh
// quotient): the weighted squared distance of its texels from their best line. m[i][k]: moment i
// of region k (w, Σw·x, Σw·x·xᵀ as Mom). Branch-free over the regions so the compiler runs it in
// vector lanes; each region's value is that of the scalar steps (an empty or flat region 0, a
// region whose power steps vanish its trace).
template <int n>
void line_residuals(const float (&m)[10][n], float out[n]) {
  for (int k = 0; k < n; ++k) {
    const float w = m[0][k];
    const float iw = 1.0f / w, mx = m[1][k] * iw, my = m[2][k] * iw, mz = m[3][k] * iw;
    const float xx = m[4][k] - m[1][k] * mx, yy = m[5][k] - m[2][k] * my, zz = m[6][k] - m[3][k] * mz;
    const float xy = m[7][k] - m[1][k] * my, xz = m[8][k] - m[1][k] * mz, yz = m[9][k] - m[2][k] * mz;
    const float trace = xx + yy + zz;
    float v0 = xx + xy + xz, v1 = xy + yy + yz, v2 = xz + yz + zz;  // C·(1,1,1): lightmaps vary along grey
    for (int it = 0; it < 2; ++it) {
      const float inv = 1.0f / trace;
      const float u0 = (xx * v0 + xy * v1 + xz * v2) * inv, u1 = (xy * v0 + yy * v1 + yz * v2) * inv,
                  u2 = (xz * v0 + yz * v1 + zz * v2) * inv;
      v0 = u0, v1 = u1, v2 = u2;
    }
    const float vv = v0 * v0 + v1 * v1 + v2 * v2;
    const float lambda =
        (v0 * (xx * v0 + xy * v1 + xz * v2) + v1 * (xy * v0 + yy * v1 + yz * v2) + v2 * (xz * v0 + yz * v1 + zz * v2)) / vv;
    const float d = trace - lambda, r = d < 0.0f ? 0.0f : d;  // std::max(d, 0)
    out[k] = !(w > 0) || !(trace > 0) ? 0.0f : !(vv > 0) ? trace : r;
  }
}

// The n partitions whose two regions lie closest to two lines, best first (ties: the lower
// number first), into best[].
void rank_partitions(const Planes& f, int n, int best[]) {
  float mean[3] = {0, 0, 0}, w = 0;
  for (int t = 0; t < 16; ++t) w += f.tw[t];
  for (int c = 0; c < 3; ++c) {
    for (int t = 0; t < 16; ++t) mean[c] += f.tw[t] * f.H[c][t];
    mean[c] /= w;
  }
  Mom tex[16], all{};
  for (int t = 0; t < 16; ++t) {
    const float x = f.H[0][t] - mean[0], y = f.H[1][t] - mean[1], z = f.H[2][t] - mean[2], tw = f.tw[t];
    const float v[10] = {tw, tw * x, tw * y, tw * z, tw * x * x, tw * y * y, tw * z * z, tw * x * y, tw * x * z, tw * y * z};
    std::memcpy(tex[t].v, v, sizeof v);
    for (int i = 0; i < 10; ++i) all.v[i] += v[i];
  }
  // Subset sums of each row of four texels, so a region costs 3 additions per moment.
  Mom rows[4][16];
  for (int g = 0; g < 4; ++g) {
    rows[g][0] = Mom{};
    for (int m = 1; m < 16; ++m) {
      const Mom& prev = rows[g][m & (m - 1)];
      const Mom& add = tex[4 * g + std::countr_zero(unsigned(m))];
      for (int i = 0; i < 10; ++i) rows[g][m].v[i] = prev.v[i] + add.v[i];
    }
  }
  // Region 0 of partition p in column p, region 1 in column 32 + p.
  float mom[10][64], res[64];
  for (int p = 0; p < 32; ++p) {
    const unsigned mask = kPartitions[p];
    for (int i = 0; i < 10; ++i) {
      const float r1 = ((rows[0][mask & 15].v[i] + rows[1][(mask >> 4) & 15].v[i]) + rows[2][(mask >> 8) & 15].v[i]) +
                       rows[3][mask >> 12].v[i];
      mom[i][32 + p] = r1, mom[i][p] = all.v[i] - r1;
    }
  }
  line_residuals(mom, res);
  std::pair<float, int> ranked[32];
  for (int p = 0; p < 32; ++p) ranked[p] = {res[p] + res[32 + p], p};
  std::partial_sort(ranked, ranked + n, ranked + 32);
  for (int i = 0; i < n; ++i) best[i] = ranked[i].second;
}

// The partition (lowest number among equals) whose region-1 mask, or its complement, differs
// least from the split of the valid texels at the midpoint of their brightness range
// (Σ half bits of the three channels).
int nearest_to_brightness_split(const Planes& f) {
  float L[16], lo = 1e30f, hi = -1e30f;
  unsigned valid = 0;
  for (int t = 0; t < 16; ++t) {
    L[t] = (f.H[0][t] + f.H[1][t]) + f.H[2][t];
    if (!f.valid[t]) continue;
    valid |= 1u << t;
    lo = std::min(lo, L[t]), hi = std::max(hi, L[t]);
  }
  const float mid = 0.5f * (lo + hi);
  unsigned mask = 0;
  for (int t = 0; t < 16; ++t) mask |= unsigned(L[t] > mid) << t;
  const int n = std::popcount(valid);
  int best = 0, best_d = 17;
  for (int p = 0; p < 32; ++p) {
    const int d = std::popcount((kPartitions[p] ^ mask) & valid), dd = std::min(d, n - d);
    if (dd < best_d) best_d = dd, best = p;
  }
  return best;
}

// Which way a gated block goes (see kColourNoise): from the weighted covariance of its half bits
// (trace and principal eigenvalue, as the one-region fit's axis) and the range of its values.
enum class Route { Search, Narrow, Edge, Skip };
Route route(const Planes& f, const float x[48], float one_err) {
  float lo = 1e30f, hi = 0, w = 0, mean[3] = {0, 0, 0};
  for (int t = 0; t < 16; ++t) {
    if (!f.valid[t]) continue;
    for (int c = 0; c < 3; ++c) lo = std::min(lo, x[t * 3 + c]), hi = std::max(hi, x[t * 3 + c]);
    w += f.tw[t];
    for (int c = 0; c < 3; ++c) mean[c] += f.tw[t] * f.H[c][t];
  }
  if (hi > kEdge * lo) return Route::Edge;
  if (!(w > 0)) return Route::Search;
  for (int c = 0; c < 3; ++c) mean[c] /= w;
  float cov[6] = {0, 0, 0, 0, 0, 0};
  for (int t = 0; t < 16; ++t) {
    if (!f.valid[t]) continue;
    const float d0 = f.H[0][t] - mean[0], d1 = f.H[1][t] - mean[1], d2 = f.H[2][t] - mean[2], tw = f.tw[t];
    cov[0] += tw * d0 * d0, cov[1] += tw * d1 * d1, cov[2] += tw * d2 * d2;
    cov[3] += tw * d0 * d1, cov[4] += tw * d0 * d2, cov[5] += tw * d1 * d2;
  }
  float ax[3], len2;
  principal_axis(cov, ax, &len2);
  const float lambda = (ax[0] * (cov[0] * ax[0] + cov[3] * ax[1] + cov[4] * ax[2]) +
                        ax[1] * (cov[3] * ax[0] + cov[1] * ax[1] + cov[5] * ax[2]) +
                        ax[2] * (cov[4] * ax[0] + cov[5] * ax[1] + cov[2] * ax[2])) / len2;
  const float trace = cov[0] + cov[1] + cov[2];
  if (!(trace - lambda > kColourNoise * trace)) return Route::Search;
  if (!(trace < kExplained * one_err)) return Route::Narrow;
  // Noise, or two clusters of different colour (which two regions fit)? The texels split at the
  // midpoint of their projections on the principal axis: two clusters put nearly all of the
  // variance between the halves, noise at most kClusters of it.
  float p[16], pmin = 1e30f, pmax = -1e30f;
  for (int t = 0; t < 16; ++t) {
    p[t] = (f.H[0][t] - mean[0]) * ax[0] + (f.H[1][t] - mean[1]) * ax[1] + (f.H[2][t] - mean[2]) * ax[2];
    if (f.valid[t]) pmin = std::min(pmin, p[t]), pmax = std::max(pmax, p[t]);
  }
  const float mid = 0.5f * (pmin + pmax);
  float wg[2] = {0, 0}, sg[2][3] = {{0, 0, 0}, {0, 0, 0}};
  for (int t = 0; t < 16; ++t) {
    if (!f.valid[t]) continue;
    const int g = p[t] > mid;
    wg[g] += f.tw[t];
    for (int c = 0; c < 3; ++c) sg[g][c] += f.tw[t] * (f.H[c][t] - mean[c]);
  }
  float between = 0;
  for (int g = 0; g < 2; ++g)
    if (wg[g] > 0) between += (sg[g][0] * sg[g][0] + sg[g][1] * sg[g][1] + sg[g][2] * sg[g][2]) / wg[g];
  return between < kClusters * trace ? Route::Skip : Route::Search;
}

// Region r's endpoint targets (half bits) from its principal axis, inside its channel ranges.
void axis_targets(const Planes& f, uint16_t mask, int r, float a[3], float b[3]) {
  float w = 0, mean[3] = {0, 0, 0}, lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (int t = 0; t < 16; ++t) {
    if (int((mask >> t) & 1) != r || !f.valid[t]) continue;
    w += f.tw[t];
    for (int c = 0; c < 3; ++c) {
      mean[c] += f.tw[t] * f.H[c][t];
      lo[c] = std::min(lo[c], f.H[c][t]), hi[c] = std::max(hi[c], f.H[c][t]);
    }
  }
  if (!(lo[0] <= hi[0])) {  // no valid texel in this region (a partial block): any endpoints
    for (int c = 0; c < 3; ++c) a[c] = b[c] = 0;
    return;
  }
  if (!(w > 0)) {
    for (int c = 0; c < 3; ++c) a[c] = lo[c], b[c] = hi[c];
    return;
  }
  for (int c = 0; c < 3; ++c) mean[c] /= w;
  float cov[6] = {0, 0, 0, 0, 0, 0};
  for (int t = 0; t < 16; ++t) {
    if (int((mask >> t) & 1) != r || !f.valid[t]) continue;
    const float d0 = f.H[0][t] - mean[0], d1 = f.H[1][t] - mean[1], d2 = f.H[2][t] - mean[2], tw = f.tw[t];
    cov[0] += tw * d0 * d0, cov[1] += tw * d1 * d1, cov[2] += tw * d2 * d2;
    cov[3] += tw * d0 * d1, cov[4] += tw * d0 * d2, cov[5] += tw * d1 * d2;
  }
  float ax[3], len2;
  principal_axis(cov, ax, &len2);
  float tmin = 1e30f, tmax = -1e30f;
  for (int t = 0; t < 16; ++t) {
    if (int((mask >> t) & 1) != r || !f.valid[t]) continue;
    const float p = (f.H[0][t] - mean[0]) * ax[0] + (f.H[1][t] - mean[1]) * ax[1] + (f.H[2][t] - mean[2]) * ax[2];
    tmin = std::min(tmin, p), tmax = std::max(tmax, p);
  }
  for (int c = 0; c < 3; ++c) {
    a[c] = std::clamp(mean[c] + tmin / len2 * ax[c], lo[c], hi[c]);
    b[c] = std::clamp(mean[c] + tmax / len2 * ax[c], lo[c], hi[c]);
  }
}

struct Cand {
  int mode = -1;  // 0-based, two-region
  int e[4][3];    // region r's endpoints are e[2r], e[2r+1]
  uint8_t idx[16];
  float err = 1e30f;
};

bool deltas_fit(const ModeInfo& mi, const int e[4][3]) {
  if (!mi.transformed) return true;
  for (int c = 0; c < 3; ++c) {
    const int lim = 1 << (mi.delta[c] - 1);
    for (int k = 1; k < 4; ++k) {
      const int d = e[k][c] - e[0][c];
      if (d < -lim || d >= lim) return false;
    }
  }
  return true;
}

// The most precise mode whose deltas fit after the anchors are fixed (texel 0 and region 1's
// anchor need an index below 4: a region whose anchor is not is mirrored, which changes no
// decoded value), with its indices and error.
Cand make(const Planes& f, int p, const float t[2][2][3], bool wide) {
  const uint16_t mask = kPartitions[p];
  const int anchor[2] = {0, kAnchor2[p]};
  Cand c;
  // The targets' spread per channel (16-bit interpolation units): all four endpoints must lie
  // within a transformed mode's delta range of one of them, which quantising (under one step per
  // endpoint) cannot change by more than two steps.
  float spread[3];
  for (int ch = 0; ch < 3; ++ch) {
    const float v[4] = {t[0][0][ch], t[0][1][ch], t[1][0][ch], t[1][1][ch]};
    spread[ch] = (std::max({v[0], v[1], v[2], v[3]}) - std::min({v[0], v[1], v[2], v[3]})) * (64.0f / 31.0f);
  }
  // Modes of equal precision come one after another in kOrder (2, 3, 4: 11 bits; 6, 7, 8: 8
  // bits) and quantise to the same endpoints, with the same indices, anchor mirrors and error:
  // only their delta checks differ, so the previous mode's work is kept for the next one.
  int q_bits = -1;          // precision of e (quantised, before the mirrors)
  bool assigned = false;    // ea, ia, erra: e after the index step, for q_bits
  int e[4][3], ea[4][3];
  uint8_t ia[16];
  float erra = 0;
  for (int m : kOrder) {
    const ModeInfo& mi = mode(m);
    if (mi.transformed) {
      bool may_fit = true;
      for (int ch = 0; ch < 3; ++ch)
        may_fit &= spread[ch] <= float(((1 << mi.delta[ch]) + 2) << (16 - mi.epb));
      if (!may_fit) continue;
    }
    if (mi.epb != q_bits) {
      for (int r = 0; r < 2; ++r)
        for (int j = 0; j < 2; ++j)
          for (int ch = 0; ch < 3; ++ch) e[2 * r + j][ch] = quantize_capped(t[r][j][ch], mi.epb, f.cap[ch]);
      q_bits = mi.epb, assigned = false;
    }
    // A mode whose deltas fit in none of the four orientations (each region either way round)
    // is skipped before the index step.
    if (mi.transformed) {
      bool any_fits = false;
      for (int o = 0; o < 4 && !any_fits; ++o) {
        int e2[4][3];
        std::memcpy(e2, e, sizeof e);
        for (int ch = 0; ch < 3; ++ch) {
          if (o & 1) std::swap(e2[0][ch], e2[1][ch]);
          if (o & 2) std::swap(e2[2][ch], e2[3][ch]);
        }
        any_fits = deltas_fit(mi, e2);
      }
      if (!any_fits) continue;
    }
    if (!assigned) {
      std::memcpy(ea, e, sizeof e);
      std::memset(ia, 0, 16);
      erra = 0;
      float er[2] = {0, 0};
      const bool both = wide;
      if (both) assign_both_avx512(f, mask, ea, mi.epb, ia, er);
      for (int r = 0; r < 2; ++r) {
        erra += both ? er[r] : assign_region(f, mask, r, ea[2 * r], ea[2 * r + 1], mi.epb, ia);
        if (ia[anchor[r]] >= 4) {
          for (int ch = 0; ch < 3; ++ch) std::swap(ea[2 * r][ch], ea[2 * r + 1][ch]);
          for (int tt = 0; tt < 16; ++tt)
            if (int((mask >> tt) & 1) == r) ia[tt] = uint8_t(7 - ia[tt]);
        }
      }
      assigned = true;
    }
    if (!deltas_fit(mi, ea)) continue;
    c.mode = m, c.err = erra;
    std::memcpy(c.e, ea, sizeof ea);
    std::memcpy(c.idx, ia, 16);
    return c;
  }
  return c;  // unreachable: the last mode always fits
}

// Up to `passes` least-squares passes on both regions' indices of `c` (partition p, endpoints `t`,
// which the passes move), each kept only when it lowers the error.
void refine(const Planes& f, int p, float (&t)[2][2][3], bool wide, int passes, Cand& c) {
  const uint16_t mask = kPartitions[p];
  for (int pass = 0; pass < passes && c.mode >= 0; ++pass) {
    bool ok = true;
    for (int r = 0; r < 2 && ok; ++r) ok = refit_region(f, mask, r, c.idx, t[r][0], t[r][1]);
    if (!ok) break;
    const Cand d = make(f, p, t, wide);
    if (!(d.mode >= 0 && d.err < c.err)) break;
    c = d;
  }
}

// Writes a two-region block from the mode's bit layout (bc6h_tables), then the indices.
void pack(const Cand& c, int p, uint8_t out[16]) {
  const ModeInfo& mi = mode(c.mode);
  uint64_t w[2] = {0, 0};
  int pos = 0;
  auto put = [&](uint32_t v, int n) {
    for (int i = 0; i < n; ++i, ++pos) w[pos >> 6] |= uint64_t((v >> i) & 1) << (pos & 63);
  };
  put(mi.code, mi.code < 2 ? 2 : 5);
  int field[12];
  for (int k = 0; k < 4; ++k)
    for (int ch = 0; ch < 3; ++ch) {
      const int v = k > 0 && mi.transformed ? c.e[k][ch] - c.e[0][ch] : c.e[k][ch];
      field[k * 3 + ch] = v & ((1 << (k > 0 ? mi.delta[ch] : mi.epb)) - 1);
    }
  for (int i = 0; i < mi.layout_count; ++i) {
    const int fi = mi.layout_field[i];
    put(uint32_t(fi == D ? p : field[fi]) >> mi.layout_bit[i], 1);
  }
  for (int t = 0; t < 16; ++t) put(c.idx[t], t == 0 || t == kAnchor2[p] ? 2 : 3);
  for (int i = 0; i < 16; ++i) out[i] = uint8_t(w[i >> 3] >> (8 * (i & 7)));
}

}  // namespace

bool improve_with_two_regions(const uint16_t h[48], const float x[48], const uint8_t valid[16], float one_err,
                              uint8_t out[16]) {
  if (!(one_err > kGate)) return false;
  Planes f;
  int first = 0;
  while (first < 15 && !valid[first]) ++first;
  for (int c = 0; c < 3; ++c) f.cap[c] = 0;
  for (int t = 0; t < 16; ++t) {
    const int s = valid[t] ? t : first;
    f.valid[t] = valid[t] ? 1 : 0;
    for (int c = 0; c < 3; ++c) {
      f.H[c][t] = float(h[s * 3 + c]);
      const float xv = std::max(x[s * 3 + c], 0.25f), slope = xv / (1.0f + xv);
      f.W[c][t] = valid[t] ? slope * slope : 0.0f;
      f.cap[c] = std::max(f.cap[c], int(h[s * 3 + c]) + 1);
    }
    f.tw[t] = (f.W[0][t] + f.W[1][t] + f.W[2][t]) * (1.0f / 3.0f);
  }
  // The index step sixteen texels at a time where the CPU has AVX-512 (the same bytes; the
  // scalar loops when forced, so tests compare the two).
  static_assert(kTried == kAvx512Partitions, "one AVX-512 lane per tried partition and region");
  const bool wide = cpu::has(cpu::kAvx512);
  const Route way = route(f, x, one_err);
  if (way == Route::Skip) return false;
  if (way == Route::Edge) {
    const int p = nearest_to_brightness_split(f);
    const uint16_t mask = kPartitions[p];
    float t[2][2][3];
    for (int r = 0; r < 2; ++r) axis_targets(f, mask, r, t[r][0], t[r][1]);
    Cand c = make(f, p, t, wide);
    refine(f, p, t, wide, kEdgeRefined, c);
    if (!(c.mode >= 0 && c.err < one_err)) return false;
    pack(c, p, out);
    return true;
  }
  const int tried = way == Route::Narrow ? kNarrowTried : kTried;
  const int refined = way == Route::Narrow ? kNarrowRefined : kRefined;
  int parts[32];
  rank_partitions(f, kTried, parts);
  // Every ranked partition from its axes; least squares only on the kRefined best of them.
  Cand cand[kTried];
  float targets[kTried][2][2][3];
  int order[kTried];
  if (wide) axis_targets_avx512(f, parts, targets);
  for (int i = 0; i < tried; ++i) {
    const uint16_t mask = kPartitions[parts[i]];
    if (!wide)
      for (int r = 0; r < 2; ++r) axis_targets(f, mask, r, targets[i][r][0], targets[i][r][1]);
    cand[i] = make(f, parts[i], targets[i], wide);
    order[i] = i;
  }
  std::stable_sort(order, order + tried, [&](int a, int b) { return cand[a].err < cand[b].err; });
  Cand best;
  int best_p = 0;
  for (int j = 0; j < tried; ++j) {
    const int i = order[j], p = parts[i];
    Cand c = cand[i];
    if (c.mode < 0) continue;
    refine(f, p, targets[i], wide, j < refined ? kPasses : 0, c);
    if (c.err < best.err) best = c, best_p = p;
  }
  if (!(best.mode >= 0 && best.err < one_err)) return false;
  pack(best, best_p, out);
  return true;
}

}  // namespace ahd::bc6h

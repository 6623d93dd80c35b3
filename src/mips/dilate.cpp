#include "mips/dilate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/parallel.h"
#include "fit/ahd_decode.h"

namespace ahd {
namespace {

// 8-neighbourhood in a fixed order (the order of the weighted sum, hence of its rounding).
constexpr int kDx[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
constexpr int kDy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
// Edge neighbours count twice as much as corner ones (they are closer: 1 vs √2 texels).
constexpr double kW[8] = {1, 2, 1, 2, 2, 1, 2, 1};

// A hint that *p will be read soon (nothing on compilers without the builtin).
inline void prefetch(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

// d[x] = min(d[x], max(k, g[x])) over a row: one step of the distance's vertical pass (a loop the
// compiler vectorises: the pointers are the row's own, restrict-qualified).
void lower_by_row(uint8_t* __restrict d, const uint8_t* __restrict g, uint8_t k, size_t n) {
  for (size_t x = 0; x < n; ++x) d[x] = std::min(d[x], std::max(k, g[x]));
}

// Eight bytes as one word (any alignment), for the scans that skip uniform runs of eight texels.
inline uint64_t load8(const uint8_t* p) {
  uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
}
inline void store8(uint8_t* p, uint64_t v) { std::memcpy(p, &v, 8); }
// Whether any of the eight bytes of v is 0 (the classic bit trick: exact, no false positives).
inline bool has_zero_byte(uint64_t v) { return ((v - 0x0101010101010101ull) & ~v & 0x8080808080808080ull) != 0; }

// Texels per distance 0 … kDilateRings + 1 ("beyond").
using RingCounts = std::array<size_t, kDilateRings + 2>;

// The ring schedule of the rule above over texel values reached through accessors: read(i, covered,
// v) copies texel i's `ch` values into v (covered: whether texel i is), write(i, v) stores them.
// Only the texels of earlier rings count, so a caller can dilate values held in any layout without
// copying them to a plane first (read may see any bits in a texel not yet filled: it must not trap).
//
// How (issue 28: the ragdoll bake's gutters take 944 rings at level 0, and a ring list found and
// sorted ring by ring was 29 % of its conversion): texel i's ring is its chessboard distance to the
// nearest covered texel (8-neighbour steps inside a rectangle: the L∞ distance), needed only up to
// kDilateRings + 1 ("beyond"). It is separable: g = each row's own distance (two scans of the
// row), then D(x, y) = min over |k| ≤ kDilateRings of max(|k|, g(x, y + k)) — exact wherever the
// distance is ≤ kDilateRings, and "beyond" elsewhere; both passes run rows in parallel, the second
// as 16 vectorised min/max sweeps per row. A counting sort by distance (per band of rows, in
// parallel) then lists every ring at once, each in row-major order. A texel of ring r has
// neighbours in rings r−1, r and r+1 only, so "filled before ring r" is "distance < r": ring r
// reads only texels of ring r−1 (or covered ones), which are final, and its values are written in
// place — each is the same sum, in the same order, as a ring-by-ring Jacobi step with a separate
// value buffer would form, whatever the threads or chunks.
//
// kCh: the channel count when known at compile time (the sums then stay in registers), 0 = `ch`.
template <int kCh, class Index, class Read, class Write, class Clear, class Touch>
void fill_by_distance(int w, int h, int ch_runtime, const std::vector<uint8_t>& coverage, int threads, DilateStats* st,
                      const Read& read, const Write& write, const Clear& clear, const Touch& touch) {
  using Dist = uint8_t;
  constexpr int kR = kDilateRings;
  constexpr Dist kBeyond = Dist(kR + 1);
  static_assert(kR + 1 < 256, "distances are bytes");
  constexpr uint64_t kBeyondWord = 0x0101010101010101ull * kBeyond;  // eight texels beyond
  const int ch = kCh > 0 ? kCh : ch_runtime;
  const size_t wn = size_t(w), hn = size_t(h), n = wn * hn;
  // Uninitialised: every element is written by its pass (one first touch, not two).
  std::unique_ptr<Dist[]> row_dist(new Dist[n]), dist(new Dist[n]);
  advise_huge_pages(row_dist.get(), n);
  advise_huge_pages(dist.get(), n);
  parallel_for(hn, threads, 16, [&](size_t y) {  // g: the distance along the row, capped
    Dist* g = row_dist.get() + y * wn;
    const uint8_t* cov = coverage.data() + y * wn;
    // Eight texels at a time where the step cannot change them (gutters far from any chart,
    // chart interiors): the scans then run at memory speed, and the bytes are the texel loop's.
    Dist run = kBeyond;
    for (size_t x = 0; x < wn;) {
      if (x + 8 <= wn) {
        const uint64_t c = load8(cov + x);
        if (c == 0 && run == kBeyond) {  // no chart: stays beyond
          store8(g + x, kBeyondWord);
          x += 8;
          continue;
        }
        if (!has_zero_byte(c)) {  // all covered
          store8(g + x, 0);
          run = 0;
          x += 8;
          continue;
        }
      }
      g[x] = run = cov[x] ? 0 : Dist(std::min<int>(run + 1, kBeyond));
      ++x;
    }
    run = kBeyond;
    for (size_t x = wn; x > 0;) {
      if (x >= 8) {
        const uint64_t v = load8(g + x - 8);
        if ((v == kBeyondWord && run == kBeyond) || v == 0) {  // min(v, anything ≥ v) = v
          run = Dist(v & 0xFF);
          x -= 8;
          continue;
        }
      }
      --x;
      g[x] = run = std::min<Dist>(g[x], Dist(std::min<int>(run + 1, kBeyond)));
    }
  });
  // Bands of rows: each counts its rings, then lists its texels at its own offsets (so the lists
  // are in row-major order whatever the threads).
  constexpr size_t kBandRows = 32;
  const size_t bands = (hn + kBandRows - 1) / kBandRows;
  std::vector<RingCounts> band_count(bands);
  parallel_for(bands, threads, 1, [&](size_t band) {
    RingCounts& count = band_count[band];
    count.fill(0);
    for (size_t y = band * kBandRows; y < std::min(hn, (band + 1) * kBandRows); ++y) {
      Dist* d = dist.get() + y * wn;
      std::copy_n(row_dist.get() + y * wn, wn, d);
      for (int k = 1; k <= kR; ++k)
        for (size_t yy : {y - size_t(k), y + size_t(k)})  // wraps below 0: then ≥ hn
          if (yy < hn) lower_by_row(d, row_dist.get() + yy * wn, Dist(k), wn);
      for (size_t x = 0; x < wn;) {
        const uint64_t v = x + 8 <= wn ? load8(d + x) : 1;  // 1: not a uniform word
        if (v == 0 || v == kBeyondWord) {
          count[v & 0xFF] += 8;
          x += 8;
        } else {
          count[d[x++]]++;
        }
      }
    }
  });
  row_dist.reset();
  RingCounts count{};
  for (const auto& c : band_count)
    for (size_t r = 0; r < count.size(); ++r) count[r] += c[r];
  uint64_t max_d = 0;
  for (size_t r = 1; r < count.size(); ++r)
    if (count[r]) max_d = r;
  // Rings by counting sort: start[r] = first slot of ring r in `order` (rings 1 … last). Texels
  // beyond kDilateRings are not listed: they are set to zero.
  const uint64_t last = std::min<uint64_t>(max_d, uint64_t(kR));
  std::vector<size_t> start(size_t(last) + 2, 0);
  for (size_t r = 2; r < start.size(); ++r) start[r] = start[r - 1] + count[r - 1];
  const size_t listed = start[size_t(last) + 1];
  std::unique_ptr<Index[]> order(new Index[std::max<size_t>(listed, 1)]);
  advise_huge_pages(order.get(), listed * sizeof(Index));
  std::vector<RingCounts> band_pos(bands);
  for (size_t band = 0; band < bands; ++band)
    for (size_t r = 1; r <= last; ++r)
      band_pos[band][r] = band == 0 ? start[r] : band_pos[band - 1][r] + band_count[band - 1][r];
  parallel_for(bands, threads, 1, [&](size_t band) {
    RingCounts pos = band_pos[band];
    const size_t end = std::min(hn, (band + 1) * kBandRows) * wn;
    for (size_t i = band * kBandRows * wn; i < end;) {
      const uint64_t v = i + 8 <= end ? load8(&dist[i]) : 1;  // 1: not a uniform word
      if (v == 0) {  // covered
        i += 8;
        continue;
      }
      if (v == kBeyondWord) {  // a run of words beyond the rings, zeroed at once
        size_t j = i + 8;
        while (j + 8 <= end && load8(&dist[j]) == kBeyondWord) j += 8;
        clear(i, j - i);
        i = j;
        continue;
      }
      const Dist d = dist[i];
      if (d > 0 && d <= last) order[pos[d]++] = Index(i);
      else if (d > last) clear(i, 1);  // beyond the rings
      ++i;
    }
  });
  st->guard = start[2] - start[1];
  st->rings = int(last);
  st->far = n - st->covered - listed;

  const Dist* dp = dist.get();
  const Index* op = order.get();
  const ptrdiff_t sw = ptrdiff_t(w), off[8] = {-sw - 1, -sw, -sw + 1, -1, 1, sw - 1, sw, sw + 1};  // kDx/kDy
  // Texels [b, e) of ring r, a fixed-order sum over the 8 neighbours of the rings before it.
  constexpr size_t kAhead = 12;
  auto fill_span = [&](uint64_t r, size_t b, size_t e) {
    double acc[16];
    float vals[16];
    std::vector<double> big;  // only for planes with more than 16 channels
    std::vector<float> bigv;
    double* a = acc;
    float* v = vals;
    if (ch > 16) {
      big.assign(size_t(ch), 0.0);
      bigv.assign(size_t(ch), 0.0f);
      a = big.data();
      v = bigv.data();
    }
    // Rings are in row-major order: rows found by stepping, not a 64-bit division per texel.
    size_t row = size_t(op[b]) / wn, row_start = row * wn;
    for (size_t s = b; s < e; ++s) {
      if (s + kAhead < e) {
        const size_t f = op[s + kAhead];
        for (size_t q : {f - std::min(f, wn), f, std::min(n - 1, f + wn)}) {
          prefetch(dp + q);
          touch(q);
        }
      }
      const size_t i = op[s];
      while (i >= row_start + wn) ++row, row_start += wn;
      const int x = int(i - row_start), y = int(row);
      for (int c = 0; c < ch; ++c) a[c] = 0.0;
      double wsum = 0;
      if (x > 0 && y > 0 && x + 1 < w && y + 1 < h) {
        // Inside the image: every neighbour is read and its term selected, not branched on (which
        // neighbours belong to earlier rings is unpredictable, and branching on it serialised the
        // neighbours' cache misses). The same sum: the skipped terms add +0.0, which leaves every
        // partial sum's bits unchanged (a sum that starts at +0 is never −0).
        for (int k = 0; k < 8; ++k) {
          const size_t j = size_t(ptrdiff_t(i) + off[k]);
          const Dist dj = dp[j];
          const bool earlier = dj < r;
          read(j, dj == 0, v);
          for (int c = 0; c < ch; ++c) a[c] += earlier ? kW[k] * double(v[c]) : 0.0;
          wsum += earlier ? kW[k] : 0.0;
        }
      } else {
        for (int k = 0; k < 8; ++k) {
          const int nx = x + kDx[k], ny = y + kDy[k];
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const size_t j = size_t(ny) * wn + size_t(nx);
          if (dp[j] >= r) continue;
          read(j, dp[j] == 0, v);
          for (int c = 0; c < ch; ++c) a[c] += kW[k] * double(v[c]);
          wsum += kW[k];
        }
      }
      for (int c = 0; c < ch; ++c) v[c] = float(a[c] / wsum);
      write(i, v);
    }
  };
  // Small rings run on the calling thread: starting threads for a few hundred texels costs more
  // than filling them (the ragdoll bake's outer rings are that small).
  constexpr size_t kChunk = 1024;
  for (uint64_t r = 1; r <= last; ++r) {
    const size_t b = start[r], e = start[r + 1];
    if (e - b <= 2 * kChunk) {
      fill_span(r, b, e);
      continue;
    }
    parallel_for((e - b + kChunk - 1) / kChunk, threads, 1,
                 [&](size_t c) { fill_span(r, b + c * kChunk, std::min(e, b + (c + 1) * kChunk)); });
  }
}

// clear(i, count) sets texels [i, i + count) to 0 (beyond the rings, or no covered texel at all).
template <int kCh = 0, class Read, class Write, class Clear, class Touch>
void dilate_rings(int w, int h, int ch, const std::vector<uint8_t>& coverage, int threads, DilateStats* stats,
                  const Read& read, const Write& write, const Clear& clear, const Touch& touch) {
  const size_t n = size_t(w) * h;
  DilateStats st;
  const size_t wn = size_t(w);
  std::vector<size_t> covered_rows(static_cast<size_t>(h), 0);
  parallel_for(size_t(h), threads, 16, [&](size_t y) {
    size_t c = 0;  // a local sum: a byte store could alias covered_rows[y], which kept the loop scalar
    for (size_t i = y * wn; i < (y + 1) * wn; ++i) c += coverage[i] ? 1 : 0;
    covered_rows[y] = c;
  });
  for (size_t c : covered_rows) st.covered += c;
  st.filled = n - st.covered;
  if (st.covered == 0) {
    // Nothing to extend: a defined value rather than whatever was there.
    clear(0, n);
    if (stats) *stats = st;
    return;
  }
  if (st.covered == n) {
    if (stats) *stats = st;
    return;
  }
  // The smallest index type that holds every texel index of this image.
  if (n <= 0xFFFFFFFFu) fill_by_distance<kCh, uint32_t>(w, h, ch, coverage, threads, &st, read, write, clear, touch);
  else fill_by_distance<kCh, size_t>(w, h, ch, coverage, threads, &st, read, write, clear, touch);
  if (stats) *stats = st;
}

}  // namespace

void dilate(ImageF& plane, const std::vector<uint8_t>& coverage, int threads, DilateStats* stats) {
  const int ch = plane.channels;
  const size_t n = plane.texels();
  if (coverage.size() != n) throw Error("dilate: coverage size does not match the image");
  if (plane.data.size() != n * size_t(ch)) throw Error("dilate: malformed image");
  float* data = plane.data.data();
  auto read = [&](size_t i, bool, float* v) { std::copy_n(data + i * size_t(ch), ch, v); };
  auto write = [&](size_t i, const float* v) { std::copy_n(v, ch, data + i * size_t(ch)); };
  auto clear = [&](size_t i, size_t count) { std::fill_n(data + i * size_t(ch), count * size_t(ch), 0.0f); };
  auto touch = [&](size_t i) { prefetch(data + i * size_t(ch)); };
  const int w = plane.width, h = plane.height;
  switch (ch) {  // the pipeline's plane widths with their sums in registers
    case 1:
      return dilate_rings<1>(w, h, 1, coverage, threads, stats, read, write, clear, touch);
    case 2:
      return dilate_rings<2>(w, h, 2, coverage, threads, stats, read, write, clear, touch);
    case 3:
      return dilate_rings<3>(w, h, 3, coverage, threads, stats, read, write, clear, touch);
    case 4:
      return dilate_rings<4>(w, h, 4, coverage, threads, stats, read, write, clear, touch);
    default:
      return dilate_rings(w, h, ch, coverage, threads, stats, read, write, clear, touch);
  }
}

void dilate_ahd(AhdImage& img, double dz_min, int threads, DilateStats* stats) {
  const size_t n = size_t(img.width) * img.height;
  const size_t nr = img.one_ratio ? 1 : 3;
  if (img.flags.size() != n || img.iz.size() != n * 3 || img.d.size() != n * 3 || img.ratio.size() != n * nr ||
      img.coverage.size() != n)
    throw Error("dilate_ahd: malformed image");
  // I_z, d and ratio as one texel of 7 or 9 values (the weights depend only on coverage, so dilating
  // them together is the same as one by one; one ratio is the mean three equal ones would have),
  // read and written in place: no plane copy of the image. The filled texels hold the raw means
  // until every ring is done, as a plane would.
  auto read = [&](size_t i, bool, float* v) {
    std::copy_n(&img.iz[i * 3], 3, v);
    std::copy_n(&img.d[i * 3], 3, v + 3);
    std::copy_n(&img.ratio[i * nr], nr, v + 6);
  };
  auto write = [&](size_t i, const float* v) {
    std::copy_n(v, 3, &img.iz[i * 3]);
    std::copy_n(v + 3, 3, &img.d[i * 3]);
    std::copy_n(v + 6, nr, &img.ratio[i * nr]);
  };
  auto clear = [&](size_t i, size_t count) {
    std::fill_n(&img.iz[i * 3], count * 3, 0.0f);
    std::fill_n(&img.d[i * 3], count * 3, 0.0f);
    std::fill_n(&img.ratio[i * nr], count * nr, 0.0f);
  };
  auto touch = [&](size_t i) {
    prefetch(&img.iz[i * 3]);
    prefetch(&img.d[i * 3]);
    prefetch(&img.ratio[i * nr]);
  };
  if (nr == 1) dilate_rings<7>(img.width, img.height, 7, img.coverage, threads, stats, read, write, clear, touch);
  else dilate_rings<9>(img.width, img.height, 9, img.coverage, threads, stats, read, write, clear, touch);
  parallel_for(n, threads, 1024, [&](size_t i) {
    if (img.coverage[i]) return;
    AhdFit f = img.texel(i);
    double d[3] = {f.d[0], f.d[1], f.d[2]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 0) {
      for (double& x : d) x /= len;
    } else {
      d[0] = d[1] = 0, d[2] = 1;  // a texel beyond the rings, or no covered texel at all (zeros)
    }
    tilt_above_horizon(d, dz_min);
    for (int c = 0; c < 3; ++c) {
      f.iz[c] = std::max(0.0f, f.iz[c]);
      f.d[c] = float(d[c]);
      // No covered texel at all: ratio 1 (pure ambient), the fit's convention for black.
      f.ratio[c] = len > 0 ? std::clamp(f.ratio[c], 0.0f, 1.0f) : 1.0f;
    }
    f.flags = 0;
    img.set_texel(i, f);
  });
}

void dilate_ambient(ShImage& sh, int threads, DilateStats* stats) {
  const size_t n = sh.texels();
  if (sh.coeffs != 1 || sh.data.size() != n * 3 || sh.coverage.size() != n)
    throw Error("dilate_ambient: needs a well-formed L0 image");
  // dilate_ahd clamps the filled I_z at 0 after the last ring; the means of values ≥ +0 are ≥ +0
  // (never −0: the sums start at +0), so clamping as each texel is written gives the same bits
  // without another pass over the level.
  auto write = [&](size_t i, const float* v) {
    for (int c = 0; c < 3; ++c) sh.texel(i)[c] = std::max(0.0f, v[c]);
  };
  auto clear = [&](size_t i, size_t count) { std::fill_n(sh.texel(i), count * 3, 0.0f); };
  // The three texels x−1 … x+1 of a neighbour row: 36 bytes, at most two cache lines.
  const float* data = sh.data.data();
  auto touch = [&, last = n - 1](size_t i) {
    prefetch(data + (i == 0 ? 0 : i - 1) * 3);
    prefetch(data + std::min(last, i + 1) * 3);
  };
  if (!sh.normals.empty()) {
    dilate_rings<3>(
        sh.width, sh.height, 3, sh.coverage, threads, stats,
        [&](size_t i, bool, float* v) { ambient_level_iz(sh, i, v); }, write, clear, touch);
    return;
  }
  // ambient_level_iz without normals, its coverage test answered by the caller (no load of
  // sh.coverage) and its branches selects.
  dilate_rings<3>(
      sh.width, sh.height, 3, sh.coverage, threads, stats,
      [&](size_t i, bool covered, float* v) {
        const float* t = sh.texel(i);
        for (int c = 0; c < 3; ++c) v[c] = covered ? l0_texel_iz(t[c]) : t[c];
      },
      write, clear, touch);
}

Image8 coverage_plane(int width, int height, const std::vector<uint8_t>& coverage) {
  if (width < 0 || height < 0 || coverage.size() != size_t(width) * height)
    throw Error("coverage_plane: coverage size does not match the image");
  Image8 out(width, height, 1);
  for (size_t i = 0; i < coverage.size(); ++i) out.data[i] = coverage[i] ? 255 : 0;
  return out;
}

}  // namespace ahd

#include "mips/dilate.h"

#include <algorithm>
#include <cmath>

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

// The ring schedule of the rule above over texel values reached through accessors: read(i, v)
// copies texel i's `ch` values into v, write(i, v) stores them. Texels are read only once covered or
// filled, so a caller can dilate values held in any layout without copying them to a plane first.
template <class Read, class Write>
void dilate_rings(int w, int h, int ch, const std::vector<uint8_t>& coverage, int threads, DilateStats* stats,
                  const Read& read, const Write& write) {
  const size_t n = size_t(w) * h;
  DilateStats st;
  // state[i]: kFilled = covered or filled by an earlier ring; kQueued = in the current or an
  // earlier ring's candidate list (one byte array for both: at level 0 each is a byte a texel).
  constexpr uint8_t kFilled = 1, kQueued = 2;
  std::vector<uint8_t> state;
  assign_large(state, n, uint8_t(0));
  const size_t wn = size_t(w);
  std::vector<size_t> covered_rows(static_cast<size_t>(h), 0);
  parallel_for(size_t(h), threads, 16, [&](size_t y) {
    for (size_t i = y * wn; i < (y + 1) * wn; ++i) {
      state[i] = coverage[i] ? kFilled | kQueued : 0;
      covered_rows[y] += coverage[i] ? 1 : 0;
    }
  });
  for (size_t c : covered_rows) st.covered += c;
  st.filled = n - st.covered;
  if (st.covered == 0) {
    // Nothing to extend: a defined value rather than whatever was there.
    const std::vector<float> zeros(size_t(ch), 0.0f);
    for (size_t i = 0; i < n; ++i) write(i, zeros.data());
    if (stats) *stats = st;
    return;
  }
  if (st.covered == n) {
    if (stats) *stats = st;
    return;
  }

  // Ring 1: uncovered texels next to a covered one, found row by row in parallel and joined in row
  // order (= the row-major scan's order: deterministic).
  std::vector<std::vector<size_t>> ring_rows(static_cast<size_t>(h));
  parallel_for(size_t(h), threads, 16, [&](size_t yy) {
    const int y = int(yy);
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * wn + size_t(x);
      if (state[i] & kFilled) continue;
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        if (coverage[size_t(ny) * wn + size_t(nx)]) {
          ring_rows[yy].push_back(i);
          break;
        }
      }
    }
  });
  std::vector<size_t> ring;
  for (const std::vector<size_t>& r : ring_rows) ring.insert(ring.end(), r.begin(), r.end());
  ring_rows = {};
  for (size_t i : ring) state[i] |= kQueued;
  st.guard = ring.size();

  std::vector<float> values;
  while (!ring.empty()) {
    st.rings++;
    // Jacobi step: every texel of the ring reads only texels filled before this ring.
    values.assign(ring.size() * size_t(ch), 0.0f);
    // Chunks of kChunk ring texels per parallel task, the texel loop inlined within a chunk (one
    // std::function call per texel cost more than the texel's arithmetic: issue 28, perf of a
    // plain 2048² bake). Each texel's sum is the same, in the same order, whatever the chunking.
    constexpr size_t kChunk = 256;
    parallel_for((ring.size() + kChunk - 1) / kChunk, threads, 1, [&](size_t chunk) {
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
      const size_t end = std::min(ring.size(), (chunk + 1) * kChunk);
      // The ring is sorted: rows found by stepping, not a 64-bit division per texel.
      size_t row = ring[chunk * kChunk] / wn, row_start = row * wn;
      for (size_t r = chunk * kChunk; r < end; ++r) {
        const size_t i = ring[r];
        while (i >= row_start + wn) ++row, row_start += wn;
        const int x = int(i - row_start), y = int(row);
        for (int c = 0; c < ch; ++c) a[c] = 0.0;
        double wsum = 0;
        for (int k = 0; k < 8; ++k) {
          const int nx = x + kDx[k], ny = y + kDy[k];
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          if (!(state[size_t(ny) * w + nx] & kFilled)) continue;
          read(size_t(ny) * w + nx, v);
          for (int c = 0; c < ch; ++c) a[c] += kW[k] * double(v[c]);
          wsum += kW[k];
        }
        for (int c = 0; c < ch; ++c) values[r * size_t(ch) + size_t(c)] = float(a[c] / wsum);
      }
    });
    for (size_t r = 0; r < ring.size(); ++r) {
      write(ring[r], &values[r * size_t(ch)]);
      state[ring[r]] |= kFilled;
    }
    // Next ring: unfilled neighbours of this ring, sorted so the order never depends on discovery.
    std::vector<size_t> next;
    size_t row = ring.front() / wn, row_start = row * wn;  // sorted: rows by stepping
    for (size_t i : ring) {
      while (i >= row_start + wn) ++row, row_start += wn;
      const int x = int(i - row_start), y = int(row);
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const size_t j = size_t(ny) * w + nx;
        if (state[j] & kQueued) continue;
        state[j] |= kQueued;
        next.push_back(j);
      }
    }
    std::sort(next.begin(), next.end());
    ring.swap(next);
  }
  if (stats) *stats = st;
}

}  // namespace

void dilate(ImageF& plane, const std::vector<uint8_t>& coverage, int threads, DilateStats* stats) {
  const int ch = plane.channels;
  const size_t n = plane.texels();
  if (coverage.size() != n) throw Error("dilate: coverage size does not match the image");
  if (plane.data.size() != n * size_t(ch)) throw Error("dilate: malformed image");
  float* data = plane.data.data();
  dilate_rings(plane.width, plane.height, ch, coverage, threads, stats,
               [&](size_t i, float* v) { std::copy_n(data + i * size_t(ch), ch, v); },
               [&](size_t i, const float* v) { std::copy_n(v, ch, data + i * size_t(ch)); });
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
  dilate_rings(img.width, img.height, int(6 + nr), img.coverage, threads, stats,
               [&](size_t i, float* v) {
                 std::copy_n(&img.iz[i * 3], 3, v);
                 std::copy_n(&img.d[i * 3], 3, v + 3);
                 std::copy_n(&img.ratio[i * nr], nr, v + 6);
               },
               [&](size_t i, const float* v) {
                 std::copy_n(v, 3, &img.iz[i * 3]);
                 std::copy_n(v + 3, 3, &img.d[i * 3]);
                 std::copy_n(v + 6, nr, &img.ratio[i * nr]);
               });
  parallel_for(n, threads, 1024, [&](size_t i) {
    if (img.coverage[i]) return;
    AhdFit f = img.texel(i);
    double d[3] = {f.d[0], f.d[1], f.d[2]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 0) {
      for (double& x : d) x /= len;
    } else {
      d[0] = d[1] = 0, d[2] = 1;  // only for an image with no covered texel (all zeros)
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
  dilate_rings(sh.width, sh.height, 3, sh.coverage, threads, stats,
               [&](size_t i, float* v) { ambient_level_iz(sh, i, v); },
               [&](size_t i, const float* v) {
                 for (int c = 0; c < 3; ++c) sh.texel(i)[c] = std::max(0.0f, v[c]);
               });
}

Image8 coverage_plane(int width, int height, const std::vector<uint8_t>& coverage) {
  if (width < 0 || height < 0 || coverage.size() != size_t(width) * height)
    throw Error("coverage_plane: coverage size does not match the image");
  Image8 out(width, height, 1);
  for (size_t i = 0; i < coverage.size(); ++i) out.data[i] = coverage[i] ? 255 : 0;
  return out;
}

}  // namespace ahd

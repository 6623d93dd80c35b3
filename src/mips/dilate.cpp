#include "mips/dilate.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/parallel.h"
#include "fit/ahd_decode.h"

namespace ahd {
namespace {

// 8-neighbourhood in a fixed order (the order of the weighted sum, hence of its rounding).
constexpr int kDx[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
constexpr int kDy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
// Edge neighbours count twice as much as corner ones (they are closer: 1 vs √2 texels).
constexpr double kW[8] = {1, 2, 1, 2, 2, 1, 2, 1};

}  // namespace

void dilate(ImageF& plane, const std::vector<uint8_t>& coverage, int threads, DilateStats* stats) {
  const int w = plane.width, h = plane.height, ch = plane.channels;
  const size_t n = plane.texels();
  if (coverage.size() != n) throw Error("dilate: coverage size does not match the image");
  if (plane.data.size() != n * size_t(ch)) throw Error("dilate: malformed image");
  DilateStats st;
  // filled[i]: 0 = not yet, 1 = covered or filled by an earlier ring.
  std::vector<uint8_t> filled(n, 0);
  for (size_t i = 0; i < n; ++i) filled[i] = coverage[i] ? 1 : 0;
  for (size_t i = 0; i < n; ++i) st.covered += filled[i];
  st.filled = n - st.covered;
  if (st.covered == 0) {
    // Nothing to extend: a defined value rather than whatever was there.
    std::fill(plane.data.begin(), plane.data.end(), 0.0f);
    if (stats) *stats = st;
    return;
  }
  if (st.covered == n) {
    if (stats) *stats = st;
    return;
  }

  // queued[i]: already in the current or an earlier ring's candidate list.
  std::vector<uint8_t> queued = filled;
  std::vector<size_t> ring;
  // Ring 1: uncovered texels next to a covered one (row-major scan = deterministic order).
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (filled[i]) continue;
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        if (filled[size_t(ny) * w + nx]) {
          ring.push_back(i);
          queued[i] = 1;
          break;
        }
      }
    }
  st.guard = ring.size();

  std::vector<float> values;
  while (!ring.empty()) {
    st.rings++;
    // Jacobi step: every texel of the ring reads only texels filled before this ring.
    values.assign(ring.size() * size_t(ch), 0.0f);
    parallel_for(ring.size(), threads, 256, [&](size_t r) {
      const size_t i = ring[r];
      const int x = int(i % size_t(w)), y = int(i / size_t(w));
      double acc[16] = {};
      std::vector<double> big;  // only for planes with more than 16 channels
      double* a = acc;
      if (ch > 16) {
        big.assign(size_t(ch), 0.0);
        a = big.data();
      }
      double wsum = 0;
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        if (!filled[size_t(ny) * w + nx]) continue;
        const float* v = plane.at(nx, ny);
        for (int c = 0; c < ch; ++c) a[c] += kW[k] * double(v[c]);
        wsum += kW[k];
      }
      for (int c = 0; c < ch; ++c) values[r * size_t(ch) + size_t(c)] = float(a[c] / wsum);
    });
    for (size_t r = 0; r < ring.size(); ++r) {
      std::copy_n(&values[r * size_t(ch)], ch, plane.at(int(ring[r] % size_t(w)), int(ring[r] / size_t(w))));
      filled[ring[r]] = 1;
    }
    // Next ring: unfilled neighbours of this ring, sorted so the order never depends on discovery.
    std::vector<size_t> next;
    for (size_t i : ring) {
      const int x = int(i % size_t(w)), y = int(i / size_t(w));
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const size_t j = size_t(ny) * w + nx;
        if (queued[j]) continue;
        queued[j] = 1;
        next.push_back(j);
      }
    }
    std::sort(next.begin(), next.end());
    ring.swap(next);
  }
  if (stats) *stats = st;
}

void dilate_ahd(AhdImage& img, double dz_min, int threads, DilateStats* stats) {
  const size_t n = size_t(img.width) * img.height;
  if (img.texels.size() != n || img.coverage.size() != n) throw Error("dilate_ahd: malformed image");
  // One 9-channel image (iz, d, ratio): the weights depend only on coverage, so dilating the three
  // planes together is the same as dilating them one by one.
  ImageF p(img.width, img.height, 9);
  for (size_t i = 0; i < n; ++i) {
    const AhdFit& f = img.texels[i];
    float* v = &p.data[i * 9];
    for (int c = 0; c < 3; ++c) {
      v[c] = f.iz[c];
      v[3 + c] = f.d[c];
      v[6 + c] = f.ratio[c];
    }
  }
  dilate(p, img.coverage, threads, stats);
  parallel_for(n, threads, 1024, [&](size_t i) {
    if (img.coverage[i]) return;
    const float* v = &p.data[i * 9];
    AhdFit& f = img.texels[i];
    double d[3] = {v[3], v[4], v[5]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 0) {
      for (double& x : d) x /= len;
    } else {
      d[0] = d[1] = 0, d[2] = 1;  // only for an image with no covered texel (all zeros)
    }
    tilt_above_horizon(d, dz_min);
    for (int c = 0; c < 3; ++c) {
      f.iz[c] = std::max(0.0f, v[c]);
      f.d[c] = float(d[c]);
      // No covered texel at all: ratio 1 (pure ambient), the fit's convention for black.
      f.ratio[c] = len > 0 ? std::clamp(v[6 + c], 0.0f, 1.0f) : 1.0f;
    }
    double ca[3], cd[3], ud[3];
    decode_colours(f.iz, f.d, f.ratio, dz_min, ca, cd, ud);
    for (int c = 0; c < 3; ++c) {
      f.ca[c] = float(ca[c]);
      f.cd[c] = float(cd[c]);
    }
    f.flags = 0;
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

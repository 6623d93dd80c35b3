#include "fit/direction_coherence.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "fit/ahd_decode.h"
#include "fit/direction_refine.h"
#include "fit/refine_objective.h"

namespace ahd {

namespace {

// Whether fs ≤ fl, where fl rounded to the nearest float is v: decided (*known) when fs lies below
// v's lower neighbour or above its upper one, which bracket fl (|fl − v| is at most half the gap
// on either side); not when v is not finite (fl overflowed or was NaN).
bool at_most_rounded(double fs, float v, bool* known) {
  *known = false;
  if (!std::isfinite(v)) return false;
  const double lo = std::nextafter(v, -INFINITY), hi = std::nextafter(v, INFINITY);
  if (fs <= lo) return *known = true, true;
  if (fs > hi) return *known = true, false;
  return false;
}

// The first pass's d and flags of three rows around row y, as the pass reads them (null outside
// the image): the neighbourhood's rows.
struct FirstRows {
  const float* d[3];
  const uint8_t* flags[3];
};

// Texel (x, y) of the pass, reading the first pass only through `rows`.
void smooth_texel(const ShImage& sh, const FitOptions& opt, const float* linear_value, const FirstRows& rows, int x,
                  int y, AhdImage* fit) {
  const int w = fit->width;
  const size_t i = size_t(y) * size_t(w) + size_t(x);
  const uint8_t flags = rows.flags[1][x];
  if (!sh.coverage[i] || (flags & (kFitNoDirection | kFitNonFinite))) return;
  double ds[3] = {0, 0, 0};
  int count = 0;
  for (int r = 0; r < 3; ++r) {
    if (!rows.d[r]) continue;
    const size_t row = size_t(y + r - 1) * size_t(w);
    for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx) {
      if (!sh.coverage[row + size_t(xx)] || (rows.flags[r][xx] & (kFitNoDirection | kFitNonFinite))) continue;
      for (int k = 0; k < 3; ++k) ds[k] += rows.d[r][size_t(xx) * 3 + size_t(k)];
      ++count;
    }
  }
  const double len = std::sqrt(ds[0] * ds[0] + ds[1] * ds[1] + ds[2] * ds[2]);
  if (count < 2 || !(len > 1e-6 * count)) return;
  for (double& v : ds) v /= len;
  tilt_above_horizon(ds, opt.dz_min);
  IrradiancePoly p[3];
  local_polys(sh, i, p);
  double iz[3];
  for (int c = 0; c < 3; ++c) iz[c] = std::max(0.0, p[c].e0 + p[c].e[2] + p[c].q[2][2]);  // as fit_texel
  const float* own = &rows.d[1][size_t(x) * 3];
  double db[3] = {own[0], own[1], own[2]}, dl[3];
  const RefineObjective f(p, iz, opt.ratio_form);
  // The mean and the texel's own d in one batch (their latencies overlap; the same bytes as two
  // value() calls), keeping the mean's moments for its colours.
  const double* two[2] = {ds, db};
  double fv[2];
  LuneMoments ms[2];
  f.values(two, 2, fv, ms);
  const double fs = fv[0], fb = fv[1];
  if (!(fs <= fb)) {
    // Worse than the texel's own: within the tolerance? (Σ_c ∫ E_c² makes f the error itself;
    // only computed here.)
    double e2 = 0;
    for (int c = 0; c < 3; ++c) e2 += hemisphere_square_integral(p[c]);
    if (!(fs - fb <= opt.coherence_tolerance * std::max(0.0, fb + e2))) return;
  }
  // Never worse than the linear d: from the first pass's value when that decides, else computed.
  bool known = false;
  bool not_worse = linear_value ? at_most_rounded(fs, linear_value[i], &known) : false;
  if (!known) {
    optimal_direction(p, opt, dl);
    tilt_above_horizon(dl, opt.dz_min);
    not_worse = fs <= f.value(dl);
  }
  if (!not_worse) return;
  AhdFit out = fit_colours(p, ds, iz, opt, &ms[0]);  // the same bytes as recomputing the moments
  out.flags |= flags;
  fit->set_texel(i, out);
}

}  // namespace

void smooth_directions(const ShImage& sh, const FitOptions& opt, int threads, AhdImage* fit,
                       const float* linear_value) {
  // In place, in bands of rows: a band works down its rows, keeping the first pass's d and flags of
  // the row above and of the current row (which it then rewrites) in two small rows; the row below
  // is still the first pass's. The rows just outside each band are kept before any band starts.
  // Every texel thus reads only the first pass, whatever the bands and threads (no copy of the
  // whole image: 13 bytes a texel).
  const int w = fit->width, h = fit->height;
  if (w <= 0 || h <= 0) return;
  const size_t row_d = size_t(w) * 3, row_f = size_t(w);
  const int band = std::clamp(4096 / w, 1, h);  // bands of ~4 K texels: jobs for every thread at 128²
  const int bands = (h + band - 1) / band;
  // Per band: [0] the row above it, [1] the row below it (when inside the image).
  std::vector<float> edge_d(size_t(bands) * 2 * row_d);
  std::vector<uint8_t> edge_f(size_t(bands) * 2 * row_f);
  for (int b = 0; b < bands; ++b) {
    const int above = b * band - 1, below = std::min(h, (b + 1) * band);
    if (above >= 0) {
      std::copy_n(&fit->d[size_t(above) * row_d], row_d, &edge_d[size_t(b) * 2 * row_d]);
      std::copy_n(&fit->flags[size_t(above) * row_f], row_f, &edge_f[size_t(b) * 2 * row_f]);
    }
    if (below < h) {
      std::copy_n(&fit->d[size_t(below) * row_d], row_d, &edge_d[(size_t(b) * 2 + 1) * row_d]);
      std::copy_n(&fit->flags[size_t(below) * row_f], row_f, &edge_f[(size_t(b) * 2 + 1) * row_f]);
    }
  }
  parallel_for(size_t(bands), threads, 1, [&](size_t b) {
    const int y0 = int(b) * band, y1 = std::min(h, y0 + band);
    std::vector<float> prev_d(row_d), cur_d(row_d);
    std::vector<uint8_t> prev_f(row_f), cur_f(row_f);
    if (y0 > 0) {
      std::copy_n(&edge_d[b * 2 * row_d], row_d, prev_d.data());
      std::copy_n(&edge_f[b * 2 * row_f], row_f, prev_f.data());
    }
    for (int y = y0; y < y1; ++y) {
      std::copy_n(&fit->d[size_t(y) * row_d], row_d, cur_d.data());
      std::copy_n(&fit->flags[size_t(y) * row_f], row_f, cur_f.data());
      FirstRows rows{{y > 0 ? prev_d.data() : nullptr, cur_d.data(), nullptr},
                     {y > 0 ? prev_f.data() : nullptr, cur_f.data(), nullptr}};
      if (y + 1 < y1) {
        rows.d[2] = &fit->d[size_t(y + 1) * row_d];
        rows.flags[2] = &fit->flags[size_t(y + 1) * row_f];
      } else if (y + 1 < h) {
        rows.d[2] = &edge_d[(b * 2 + 1) * row_d];
        rows.flags[2] = &edge_f[(b * 2 + 1) * row_f];
      }
      for (int x = 0; x < w; ++x) smooth_texel(sh, opt, linear_value, rows, x, y, fit);
      std::swap(prev_d, cur_d);
      std::swap(prev_f, cur_f);
    }
  });
}

}  // namespace ahd

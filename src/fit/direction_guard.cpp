#include "fit/direction_guard.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/parallel.h"

namespace ahd {

double neighbour_angle_deg(const float u[3], const float v[3]) {
  const double dot = double(u[0]) * v[0] + double(u[1]) * v[1] + double(u[2]) * v[2];
  return std::acos(std::clamp(dot, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

namespace {

// True when the pair (i, j) breaks the bound: its stored angle exceeds max(T, its linear angle).
// Most pairs turn far less than T: their dot product alone clears them (cos_t is cos T less a
// margin far above acos's rounding, so no pair the exact test would flag is cleared).
bool violates(const AhdImage& fit, const std::vector<float>& lin, const std::vector<float>* also, size_t i, size_t j,
              double t_deg, double cos_t) {
  const float* u = &fit.d[i * 3];
  const float* v = &fit.d[j * 3];
  const double dot = double(u[0]) * v[0] + double(u[1]) * v[1] + double(u[2]) * v[2];
  if (dot > cos_t) return false;
  const double a = neighbour_angle_deg(u, v);
  if (!(a > t_deg)) return false;
  return a > neighbour_angle_deg(&lin[i * 3], &lin[j * 3]) &&
         (!also || a > neighbour_angle_deg(&(*also)[i * 3], &(*also)[j * 3]));
}

}  // namespace

size_t guard_direction_pairs(const ShImage& sh, const FitOptions& opt, const std::vector<float>& linear_d,
                             int threads, AhdImage* fit, const std::function<AhdFit(size_t)>& revert,
                             const std::vector<float>* also_d) {
  const size_t w = size_t(fit->width), h = size_t(fit->height), n = w * h;
  const double t_deg = opt.pair_guard_deg;
  const double cos_t = std::cos(t_deg * 3.14159265358979323846 / 180.0) + 1e-9;
  FitOptions lin_opt = opt;
  lin_opt.direction_fit = DirectionFit::Linear;
  std::vector<uint8_t> reverted(n, 0), mark(n, 0);
  // Texel i breaks the bound with one of its (up to 4) covered neighbours, given the current state.
  auto breaks = [&](size_t i) {
    if (!sh.coverage[i]) return false;
    const size_t x = i % w, y = i / w;
    return (x > 0 && sh.coverage[i - 1] && violates(*fit, linear_d, also_d, i, i - 1, t_deg, cos_t)) ||
           (x + 1 < w && sh.coverage[i + 1] && violates(*fit, linear_d, also_d, i, i + 1, t_deg, cos_t)) ||
           (y > 0 && sh.coverage[i - w] && violates(*fit, linear_d, also_d, i, i - w, t_deg, cos_t)) ||
           (y + 1 < h && sh.coverage[i + w] && violates(*fit, linear_d, also_d, i, i + w, t_deg, cos_t));
  };
  // Sweep 0 checks every texel; later sweeps only the unreverted neighbours of the texels the sweep
  // before reverted (no other pair changed). The candidates of a sweep are decided against one
  // state (marks first, reverts after), in ascending order: nothing depends on the thread count.
  std::vector<size_t> candidates, fresh;
  // Sweep 0 tests each pair once: bit 1 its right pair, bit 2 its lower pair (each item writes only
  // its own byte), then a texel breaks when one of its four pairs does.
  parallel_for(n, threads, 4096, [&](size_t i) {
    if (!sh.coverage[i]) return;
    const size_t x = i % w, y = i / w;
    mark[i] = uint8_t((x + 1 < w && sh.coverage[i + 1] && violates(*fit, linear_d, also_d, i, i + 1, t_deg, cos_t) ? 1 : 0) |
                      (y + 1 < h && sh.coverage[i + w] && violates(*fit, linear_d, also_d, i, i + w, t_deg, cos_t) ? 2 : 0));
  });
  for (size_t y = 0, i = 0; y < h; ++y)
    for (size_t x = 0; x < w; ++x, ++i)
      if ((mark[i] & 3) || (x > 0 && (mark[i - 1] & 1)) || (y > 0 && (mark[i - w] & 2))) fresh.push_back(i);
  std::fill(mark.begin(), mark.end(), uint8_t(0));
  size_t total = 0;
  while (!fresh.empty()) {
    parallel_for(fresh.size(), threads, 64, [&](size_t k) {
      const size_t i = fresh[k];
      if (revert) return fit->set_texel(i, revert(i));
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      fit->set_texel(i, fit_texel(p, lin_opt));
    });
    for (size_t i : fresh) reverted[i] = 1, mark[i] = 0;
    total += fresh.size();
    candidates.clear();
    for (size_t i : fresh) {
      const size_t x = i % w, y = i / w;
      const size_t nb[4] = {x > 0 ? i - 1 : n, x + 1 < w ? i + 1 : n, y > 0 ? i - w : n, y + 1 < h ? i + w : n};
      for (size_t j : nb)
        if (j < n && !reverted[j] && !mark[j]) mark[j] = 2, candidates.push_back(j);  // 2: queued
    }
    std::sort(candidates.begin(), candidates.end());
    parallel_for(candidates.size(), threads, 256, [&](size_t k) { mark[candidates[k]] = breaks(candidates[k]); });
    fresh.clear();
    for (size_t i : candidates)
      if (mark[i]) fresh.push_back(i);
    for (size_t i : candidates) mark[i] = 0;
  }
  return total;
}

}  // namespace ahd

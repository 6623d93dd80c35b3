#include "cli/source_error.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/parallel.h"
#include "fit/covered_slots.h"
#include "fit/hemisphere_error.h"
#include "sh/sh.h"

namespace ahd::cli {

namespace {

const double kSourceLuma[3] = {0.2126, 0.7152, 0.0722};

// The value at sorted index ceil(0.99·n) − 1 (the reports' p99); reorders v.
double source_p99(std::vector<double>& v) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, size_t(std::ceil(0.99 * double(v.size()))) - 1);
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

// One covered texel: RMS error over the hemisphere against max(0, E), the report's log2 figure
// (texel_error), and the source's luminance over the hemisphere and along the normal (the
// denominators before the floor).
struct SourceTexel {
  double rmse = 0, lg = 0, lum = 0, ez_err = 0, ez_lum = 0;
};

}  // namespace

SourceErrorFigures measure_against_source(const ShImage& sh, const DecodedPlanes& level0, double dz_min, double floor) {
  const int nd = 64;
  const std::vector<double> dirs = hemisphere_directions(nd);
  const std::vector<AhdLobe> lobes = lobes_from_planes(level0, dz_min);
  const size_t n = sh.texels();
  size_t covered = 0;
  const std::vector<size_t> slot = covered_slots(sh, &covered);
  std::vector<SourceTexel> t(covered);
  parallel_for(n, 0, 512, [&](size_t i) {
    if (!sh.coverage[i]) return;
    const TexelError e = texel_error(sh, i, lobes[i], dirs.data(), nd);
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    SourceTexel& x = t[slot[i]];
    x.lg = e.lg;
    double lum = 0, se = 0;
    const AhdLobe& lb = lobes[i];
    for (int k = 0; k < nd; ++k) {
      const double* w = &dirs[size_t(k) * 3];
      const double cosine = std::max(0.0, w[0] * lb.d[0] + w[1] * lb.d[1] + w[2] * lb.d[2]);
      for (int c = 0; c < 3; ++c) {
        // Negative irradiance (the truncated SH's ringing) is black on screen and out of reach of
        // any non-negative decode: the reference is E clamped at 0, as along the normal.
        const double ref = std::max(0.0, eval_irradiance(p[c], w));
        const double got = lb.ca[c] + cosine * lb.cd[c];
        lum += kSourceLuma[c] * ref;
        se += (got - ref) * (got - ref);
      }
    }
    x.lum = lum / nd;
    x.rmse = std::sqrt(se / (3.0 * nd));
    const double z[3] = {0, 0, 1};
    for (int c = 0; c < 3; ++c) {
      const double ref = std::max(0.0, eval_irradiance(p[c], z));
      const double got = lb.ca[c] + std::max(0.0, lb.d[2]) * lb.cd[c];
      x.ez_lum += kSourceLuma[c] * ref;
      x.ez_err = std::max(x.ez_err, std::fabs(got - ref));
    }
  });
  SourceErrorFigures f;
  f.texels = covered;
  if (!covered) return f;
  std::vector<double> v(covered);
  for (size_t i = 0; i < covered; ++i) v[i] = t[i].lum;
  f.scale = std::max(0.0, source_p99(v));
  for (size_t i = 0; i < covered; ++i) v[i] = t[i].ez_lum;
  f.iz_scale = std::max(0.0, source_p99(v));
  // A zero denominator (a black image, or a black texel with no floor): no error is 0, any is ∞.
  const auto ratio = [](double err, double den) { return den > 0 ? err / den : (err > 0 ? INFINITY : 0.0); };
  double lg = 0;
  for (size_t i = 0; i < covered; ++i) {
    const double den = std::max(t[i].lum, floor * f.scale);
    f.floored += den > t[i].lum;
    v[i] = ratio(t[i].rmse, den);
    lg += t[i].lg;
  }
  f.rel_p99 = source_p99(v);
  f.log_rmse = lg / double(covered);
  for (size_t i = 0; i < covered; ++i) v[i] = ratio(t[i].ez_err, std::max(t[i].ez_lum, floor * f.iz_scale));
  f.iz_rel_p99 = source_p99(v);
  return f;
}

}  // namespace ahd::cli

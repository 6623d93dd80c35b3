#include "fit/hemisphere_error.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace ahd {
namespace {

ErrorStat summarise(std::vector<double> v) {
  ErrorStat s;
  if (v.empty()) return s;
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / double(v.size());
  std::sort(v.begin(), v.end());
  s.max = v.back();
  s.p99 = v[std::min(v.size() - 1, size_t(std::ceil(0.99 * double(v.size()))) - 1)];
  return s;
}

const double kLuma[3] = {0.2126, 0.7152, 0.0722};

// One direction w of one texel: the lobe's and the SH's irradiance per channel.
inline void evaluate_both(const IrradiancePoly p[3], const AhdLobe& l, const double* w, double got[3], double ref[3]) {
  const double cosine = std::max(0.0, w[0] * l.d[0] + w[1] * l.d[1] + w[2] * l.d[2]);
  for (int c = 0; c < 3; ++c) {
    ref[c] = eval_irradiance(p[c], w);
    got[c] = l.ca[c] + cosine * l.cd[c];
  }
}

// The `relative` figure of one texel: RMS over directions and channels / mean luminance irradiance.
double texel_relative(double se, double mean_lum_sum, int directions) {
  const double mean_lum = mean_lum_sum / directions;
  const double rmse = std::sqrt(se / (3.0 * directions));
  return mean_lum > 0 ? rmse / mean_lum : 0.0;
}

}  // namespace

std::vector<double> hemisphere_directions(int count) {
  std::vector<double> dirs(size_t(count) * 3);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (i + 0.5) / count;  // uniform in z = uniform in solid angle
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    dirs[size_t(i) * 3 + 0] = r * std::cos(golden * i);
    dirs[size_t(i) * 3 + 1] = r * std::sin(golden * i);
    dirs[size_t(i) * 3 + 2] = z;
  }
  return dirs;
}

ErrorReport measure_error(const ShImage& sh, const std::vector<AhdLobe>& lobes, int threads,
                          int directions) {
  const std::vector<double> dirs = hemisphere_directions(directions);
  const size_t n = sh.texels();
  std::vector<double> rmse(n, -1), rel(n, -1), lg(n, -1), nrel(n, -1);
  std::vector<uint8_t> neg(n, 0);
  parallel_for(n, threads, 512, [&](size_t i) {
    if (!sh.coverage[i]) return;
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const AhdLobe& l = lobes[i];
    double se = 0, sl = 0, lum_sum = 0;
    for (int k = 0; k < directions; ++k) {
      double got[3], ref[3];
      evaluate_both(p, l, &dirs[size_t(k) * 3], got, ref);
      for (int c = 0; c < 3; ++c) {
        se += (got[c] - ref[c]) * (got[c] - ref[c]);
        const double dl = std::log2(1.0 + std::max(0.0, got[c])) - std::log2(1.0 + std::max(0.0, ref[c]));
        sl += dl * dl;
        lum_sum += kLuma[c] * ref[c];
      }
    }
    rmse[i] = std::sqrt(se / (3.0 * directions));
    rel[i] = texel_relative(se, lum_sum, directions);
    lg[i] = std::sqrt(sl / (3.0 * directions));
    const double z[3] = {0, 0, 1};
    double ez_lum = 0, ez_err = 0;
    for (int c = 0; c < 3; ++c) {
      const double ref = std::max(0.0, eval_irradiance(p[c], z));
      const double got = l.ca[c] + std::max(0.0, l.d[2]) * l.cd[c];
      ez_lum += kLuma[c] * ref;
      ez_err = std::max(ez_err, std::fabs(got - ref));
    }
    nrel[i] = ez_lum > 0 ? ez_err / ez_lum : 0.0;
    for (int c = 0; c < 3; ++c) neg[i] |= (l.ca[c] < 0 || l.cd[c] < 0);
  });
  auto covered = [&](const std::vector<double>& v) {
    std::vector<double> out;
    out.reserve(n);
    for (size_t i = 0; i < n; ++i)
      if (sh.coverage[i]) out.push_back(v[i]);
    return out;
  };
  ErrorReport r;
  for (size_t i = 0; i < n; ++i) {
    r.texels += sh.coverage[i] != 0;
    r.negative += neg[i];
  }
  r.rmse = summarise(covered(rmse));
  r.relative = summarise(covered(rel));
  r.log2 = summarise(covered(lg));
  r.normal_rel = summarise(covered(nrel));
  return r;
}

bool relative_p99_exceeds(const ShImage& sh, const std::vector<AhdLobe>& lobes, double threshold, int directions) {
  size_t covered = 0;
  for (uint8_t c : sh.coverage) covered += c != 0;
  if (covered == 0) return false;
  // summarise(): p99 is the value at sorted index ceil(0.99·n) − 1, so it exceeds the threshold
  // exactly when at least n − that index texels do. Stop as soon as that many are found.
  const size_t needed = covered - (size_t(std::ceil(0.99 * double(covered))) - 1);
  const std::vector<double> dirs = hemisphere_directions(directions);
  size_t above = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!sh.coverage[i]) continue;
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    double se = 0, lum_sum = 0;
    for (int k = 0; k < directions; ++k) {
      double got[3], ref[3];
      evaluate_both(p, lobes[i], &dirs[size_t(k) * 3], got, ref);
      for (int c = 0; c < 3; ++c) se += (got[c] - ref[c]) * (got[c] - ref[c]), lum_sum += kLuma[c] * ref[c];
    }
    if (texel_relative(se, lum_sum, directions) > threshold && ++above >= needed) return true;
  }
  return false;
}

}  // namespace ahd

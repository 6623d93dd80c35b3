#include "lab/fit_quality.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/parallel.h"
#include "fit/ahd_decode.h"
#include "fit/direction_guard.h"
#include "fit/direction_refine.h"
#include "fit/hemisphere_error.h"
#include "lab/hard_cases.h"

namespace ahd {
namespace {

const double kLuma[3] = {0.2126, 0.7152, 0.0722};

// √(Σ_c ∫_{Ω+} (C_a + C_d max(0,ω·d) − E_c)² / (3·2π)) for a decoded lobe.
double lobe_rms(const IrradiancePoly p[3], const double ca[3], const double cd[3], const double d[3]) {
  double se = 0;
  for (int c = 0; c < 3; ++c) se += hemisphere_mse(hemisphere_moments(p[c], d), ca[c], cd[c]);
  return std::sqrt(se / 3.0);
}

double planes_rms(const IrradiancePoly p[3], const float iz[3], const float d[3], const float ratio[3],
                  double dz_min) {
  double ca[3], cd[3], u[3];
  decode_colours(iz, d, ratio, dz_min, ca, cd, u);
  return lobe_rms(p, ca, cd, u);
}

// The unconstrained LS lobe at the linear d (after the horizon rule).
void ls_lobe(const IrradiancePoly p[3], const FitOptions& opt, double ca[3], double cd[3], double d[3]) {
  optimal_direction(p, opt, d);
  tilt_above_horizon(d, opt.dz_min);
  for (int c = 0; c < 3; ++c) fit_channel_unconstrained(hemisphere_moments(p[c], d, false), &ca[c], &cd[c]);
}

// RMS over the sampled normals `dirs` (count × 3) and the three channels.
double sampled_rms(const IrradiancePoly p[3], const double ca[3], const double cd[3], const double d[3],
                   const std::vector<double>& dirs) {
  const size_t n = dirs.size() / 3;
  double se = 0;
  for (size_t k = 0; k < n; ++k) {
    const double* w = &dirs[k * 3];
    const double g = std::max(0.0, w[0] * d[0] + w[1] * d[1] + w[2] * d[2]);
    for (int c = 0; c < 3; ++c) {
      const double e = ca[c] + g * cd[c] - eval_irradiance(p[c], w);
      se += e * e;
    }
  }
  return n ? std::sqrt(se / (3.0 * double(n))) : 0.0;
}

// rgb ← grey·(1−s) + s·rgb with grey = scale·(one uniform draw); no draw when s = 1 (so the
// independent-colour set keeps its texels).
void mix_colour(double rgb[3], double scale, double s, std::mt19937& rng) {
  if (s == 1.0) return;
  const double grey = scale * std::uniform_real_distribution<double>(0, 1)(rng);
  for (int c = 0; c < 3; ++c) rgb[c] = grey * (1.0 - s) + s * rgb[c];
}

}  // namespace

FitQuality fit_quality(const ShImage& sh, const AhdImage& fit, const FitOptions& opt, int threads,
                       int directions) {
  const size_t n = sh.texels();
  const std::vector<double> dirs = hemisphere_directions(std::max(0, directions));
  std::vector<double> f(n, 0), l(n, 0), m(n, 0), sf(n, 0), sl(n, 0);
  parallel_for(n, threads, 256, [&](size_t i) {
    if (!sh.coverage[i]) return;
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const AhdFit t = fit.texel(i);
    double ca[3], cd[3], u[3], lca[3], lcd[3], ld[3];
    decode_colours(t.iz, t.d, t.ratio, opt.dz_min, ca, cd, u);
    ls_lobe(p, opt, lca, lcd, ld);
    f[i] = lobe_rms(p, ca, cd, u);
    l[i] = lobe_rms(p, lca, lcd, ld);
    if (!dirs.empty()) sf[i] = sampled_rms(p, ca, cd, u, dirs), sl[i] = sampled_rms(p, lca, lcd, ld, dirs);
    for (int c = 0; c < 3; ++c) m[i] += kLuma[c] * hemisphere_integral(p[c]) / (2.0 * kPi);
  });
  size_t nratio = 0, nsampled = 0;
  double sum_sf = 0, sum_sl = 0;
  FitQuality q;
  q.directions = int(dirs.size() / 3);
  for (size_t i = 0; i < n; ++i) {
    if (!sh.coverage[i]) continue;
    q.texels++;
    q.fit_rms += f[i];
    q.ls_rms += l[i];
    if (m[i] > 0) q.fit_rel += f[i] / m[i], q.ls_rel += l[i] / m[i];
    if (l[i] > 0) q.texel_ratio += f[i] / l[i], nratio++;
    sum_sf += sf[i], sum_sl += sl[i];
    if (sl[i] > 1e-6 * std::fabs(m[i])) q.sampled_texel_ratio += sf[i] / sl[i], nsampled++;
  }
  if (q.texels) q.fit_rms /= double(q.texels), q.ls_rms /= double(q.texels);
  if (q.texels) q.fit_rel /= double(q.texels), q.ls_rel /= double(q.texels);
  if (nratio) q.texel_ratio /= double(nratio);
  if (nsampled) q.sampled_texel_ratio /= double(nsampled);
  q.sampled_ratio = sum_sl > 0 ? sum_sf / sum_sl : 1.0;
  return q;
}

double direction_p99_angle_deg(const AhdImage& fit) {
  std::vector<double> angles;
  auto add = [&](size_t a, size_t b) {
    if (!fit.coverage[a] || !fit.coverage[b]) return;
    angles.push_back(neighbour_angle_deg(&fit.d[a * 3], &fit.d[b * 3]));  // the pair guard's angle
  };
  for (int y = 0; y < fit.height; ++y)
    for (int x = 0; x < fit.width; ++x) {
      const size_t i = size_t(y) * fit.width + x;
      if (x + 1 < fit.width) add(i, i + 1);
      if (y + 1 < fit.height) add(i, i + fit.width);
    }
  if (angles.empty()) return 0.0;
  std::sort(angles.begin(), angles.end());
  return angles[std::min(angles.size() - 1, size_t(std::ceil(0.99 * double(angles.size()))) - 1)];
}

FilteredError filtered_error(const ShImage& sh, const AhdImage& fit, const FitOptions& opt) {
  static const double kPos[5][2] = {{0.25, 0.25}, {0.5, 0.5}, {0.75, 0.75}, {0.5, 0.0}, {0.0, 0.5}};
  FilteredError out;
  for (int y = 0; y + 1 < sh.height; ++y)
    for (int x = 0; x + 1 < sh.width; ++x) {
      const size_t idx[4] = {size_t(y) * sh.width + x, size_t(y) * sh.width + x + 1,
                             size_t(y + 1) * sh.width + x, size_t(y + 1) * sh.width + x + 1};
      bool all = true;
      for (size_t i : idx) all = all && sh.coverage[i];
      if (!all) continue;
      IrradiancePoly p[4][3];
      for (int k = 0; k < 4; ++k) local_polys(sh, idx[k], p[k]);
      for (const auto& pos : kPos) {
        const double w[4] = {(1 - pos[0]) * (1 - pos[1]), pos[0] * (1 - pos[1]), (1 - pos[0]) * pos[1],
                             pos[0] * pos[1]};
        // Every plane and the SH (its polynomial is linear in the coefficients) filter the same way.
        float iz[3] = {}, d[3] = {}, r[3] = {};
        IrradiancePoly q[3];
        for (int k = 0; k < 4; ++k) {
          const AhdFit t = fit.texel(idx[k]);
          for (int c = 0; c < 3; ++c) {
            iz[c] += float(w[k] * t.iz[c]), d[c] += float(w[k] * t.d[c]), r[c] += float(w[k] * t.ratio[c]);
            q[c].e0 += w[k] * p[k][c].e0;
            for (int i = 0; i < 3; ++i) {
              q[c].e[i] += w[k] * p[k][c].e[i];
              for (int j = 0; j < 3; ++j) q[c].q[i][j] += w[k] * p[k][c].q[i][j];
            }
          }
        }
        out.rms += planes_rms(q, iz, d, r, opt.dz_min);
        double lum = 0;
        for (int c = 0; c < 3; ++c) lum += kLuma[c] * hemisphere_integral(q[c]) / (2.0 * kPi);
        out.mean_irradiance += lum;
        out.samples++;
      }
    }
  if (out.samples) out.rms /= double(out.samples), out.mean_irradiance /= double(out.samples);
  return out;
}

ShImage random_lighting_set(int n, uint32_t seed, double saturation, double ambient) {
  ShImage img = make_sh_image(n, 1, 9);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  for (int i = 0; i < n; ++i) {
    float* sh = img.texel(size_t(i));
    const double scale = std::pow(10.0, u(rng) * 4 - 2);
    const int lights = 1 + int(u(rng) * 3);
    for (int l = 0; l < lights; ++l) {
      double d[3] = {g(rng), g(rng), g(rng)};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double& v : d) v /= len;
      double rgb[3] = {scale * u(rng), scale * u(rng), scale * u(rng)};
      mix_colour(rgb, scale, saturation, rng);
      add_directional_light(sh, 9, d, rgb);
    }
    double amb[3] = {scale * ambient * u(rng), scale * ambient * u(rng), scale * ambient * u(rng)};
    mix_colour(amb, scale * ambient, saturation, rng);
    add_ambient(sh, amb);
  }
  return img;
}

}  // namespace ahd

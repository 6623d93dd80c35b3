#include "lab/truth_reference.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/parallel.h"
#include "fit/ahd_decode.h"
#include "fit/ahd_fit.h"
#include "sh/sh.h"
#include "sh/sh_image.h"

namespace ahd {

namespace {

constexpr int kBins = 64;
constexpr int kIterations = 300;  // the representations' errors move by < 0.3 % from 200 on (docs/accuracy-real-lighting.md)

// The hemisphere bins (Fibonacci spiral, equal solid angle 2π/kBins each).
std::vector<std::array<double, 3>> hemisphere_bins() {
  std::vector<std::array<double, 3>> b(kBins);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int j = 0; j < kBins; ++j) {
    const double z = 1.0 - (j + 0.5) / kBins, r = std::sqrt(1.0 - z * z);
    b[j] = {r * std::cos(golden * j), r * std::sin(golden * j), z};
  }
  return b;
}

// The problem every texel shares: G = AᵀA + λI (A: training normals × bins, max(0, n·ω) Δω), the
// rows of A, and the step 1/‖G‖ of the projected gradient.
struct Nnls {
  std::vector<double> a;  // training × kBins
  std::vector<double> g;  // kBins × kBins
  double step = 0;
  size_t rows = 0;
};

Nnls make_nnls(const TruthSet& t, const std::vector<std::array<double, 3>>& bins) {
  Nnls p;
  const double dw = 2.0 * kPi / kBins;
  for (size_t k = 0; k < t.normals.size(); ++k) {
    if (t.held_out[k]) continue;
    const auto& n = t.normals[k];
    for (const auto& w : bins) p.a.push_back(std::max(0.0, n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) * dw);
    ++p.rows;
  }
  p.g.assign(size_t(kBins) * kBins, 0.0);
  double trace = 0;
  for (int i = 0; i < kBins; ++i)
    for (int j = 0; j < kBins; ++j) {
      double s = 0;
      for (size_t r = 0; r < p.rows; ++r) s += p.a[r * kBins + i] * p.a[r * kBins + j];
      p.g[size_t(i) * kBins + j] = s;
      if (i == j) trace += s;
    }
  const double lambda = 1e-3 * trace / kBins;  // small: picks the smoothest of the exact fits
  for (int i = 0; i < kBins; ++i) p.g[size_t(i) * kBins + i] += lambda;
  std::vector<double> v(kBins, 1.0), w(kBins);  // power iteration for the largest eigenvalue
  double norm = 0;
  for (int it = 0; it < 100; ++it) {
    norm = 0;
    for (int i = 0; i < kBins; ++i) {
      double s = 0;
      for (int j = 0; j < kBins; ++j) s += p.g[size_t(i) * kBins + j] * v[j];
      w[i] = s, norm += s * s;
    }
    norm = std::sqrt(norm);
    for (int i = 0; i < kBins; ++i) v[i] = w[i] / norm;
  }
  p.step = 1.0 / norm;
  return p;
}

// min ½LᵀGL − bᵀL over L ≥ 0 (accelerated projected gradient, fixed iteration count).
void solve_radiance(const Nnls& p, const double* b, double* l) {
  std::vector<double> y(kBins, 0.0), prev(kBins, 0.0);
  std::fill(l, l + kBins, 0.0);
  double tk = 1.0;
  for (int it = 0; it < kIterations; ++it) {
    for (int i = 0; i < kBins; ++i) {
      double grad = -b[i];
      for (int j = 0; j < kBins; ++j) grad += p.g[size_t(i) * kBins + j] * y[j];
      prev[i] = l[i];
      l[i] = std::max(0.0, y[i] - p.step * grad);
    }
    const double tn = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * tk * tk));
    for (int i = 0; i < kBins; ++i) y[i] = l[i] + (tk - 1.0) / tn * (l[i] - prev[i]);
    tk = tn;
  }
}

}  // namespace

ShImage baker_sh(const TruthSet& t, int coeffs, int threads) {
  const auto bins = hemisphere_bins();
  const Nnls p = make_nnls(t, bins);
  std::vector<double> basis(size_t(kBins) * 9);
  for (int j = 0; j < kBins; ++j) sh_basis(bins[j][0], bins[j][1], bins[j][2], 9, &basis[size_t(j) * 9]);
  ShImage sh = make_sh_image(t.width, t.height, coeffs);
  sh.coverage = t.coverage;
  const double dw = 2.0 * kPi / kBins;
  parallel_for(t.texels(), threads, 64, [&](size_t i) {
    if (!t.coverage[i]) return;
    float* out = sh.texel(i);
    for (int c = 0; c < 3; ++c) {
      double b[kBins] = {}, l[kBins];
      size_t r = 0;
      for (size_t k = 0; k < t.normals.size(); ++k) {
        if (t.held_out[k]) continue;
        const double e = t.e[k][i * 3 + c];
        for (int j = 0; j < kBins; ++j) b[j] += p.a[r * kBins + j] * e;
        ++r;
      }
      solve_radiance(p, b, l);
      for (int k = 0; k < coeffs; ++k) {
        double s = 0;
        for (int j = 0; j < kBins; ++j) s += l[j] * basis[size_t(j) * 9 + k] * dw;
        out[k * 3 + c] = float(s);
      }
    }
  });
  return sh;
}


TruthErrors truth_errors(const TruthSet& t, const TruthEval& eval) {
  double num = 0, den = 0, bnum = 0, bden = 0;
  for (size_t i = 0; i < t.texels(); ++i) {
    if (!t.coverage[i]) continue;
    double out[3];
    for (size_t k = 0; k < t.normals.size(); ++k) {
      if (!t.held_out[k]) continue;
      eval(i, t.normals[k].data(), out);
      for (int c = 0; c < 3; ++c) num += std::fabs(out[c] - t.e[k][i * 3 + c]), den += std::fabs(t.e[k][i * 3 + c]);
    }
    const double nb[3] = {t.bumped_n[i * 3], t.bumped_n[i * 3 + 1], t.bumped_n[i * 3 + 2]};
    eval(i, nb, out);
    for (int c = 0; c < 3; ++c) bnum += std::fabs(out[c] - t.bumped_e[i * 3 + c]), bden += std::fabs(t.bumped_e[i * 3 + c]);
  }
  return {num / den, bnum / bden};
}

TruthPairEval mean_of_pair(const TruthEval& eval) {
  return [eval](size_t i, size_t j, const double n[3], double out[3]) {
    double a[3], b[3];
    eval(i, n, a);
    eval(j, n, b);
    for (int c = 0; c < 3; ++c) out[c] = 0.5 * (a[c] + b[c]);
  };
}

double truth_between_error(const TruthSet& t, const TruthPairEval& eval) {
  double num = 0, den = 0;
  const size_t w = size_t(t.width);
  for (size_t i = 0; i < t.texels(); ++i) {
    if (!t.coverage[i]) continue;
    const size_t x = i % w;
    for (const size_t j : {x + 1 < w ? i + 1 : i, i + w < t.texels() ? i + w : i}) {
      if (j == i || !t.coverage[j]) continue;
      for (size_t k = 0; k < t.normals.size(); ++k) {
        if (!t.held_out[k]) continue;
        double out[3];
        eval(i, j, t.normals[k].data(), out);
        for (int c = 0; c < 3; ++c) {
          const double e = 0.5 * (t.e[k][i * 3 + c] + t.e[k][j * 3 + c]);
          num += std::fabs(out[c] - e), den += std::fabs(e);
        }
      }
    }
  }
  return den > 0 ? num / den : 0.0;
}

TruthEval ahd_image_eval(const AhdImage& a, double dz_min) {
  return [&a, dz_min](size_t i, const double n[3], double out[3]) {
    const AhdFit f = a.texel(i);
    decode_irradiance(f.iz, f.d, f.ratio, n, dz_min, out);
  };
}

void truth_mid_planes(const float* iz, const float* d, const float* r, size_t i, size_t j, size_t rs, float m[9]) {
  for (int c = 0; c < 3; ++c) {
    m[c] = 0.5f * (iz[i * 3 + c] + iz[j * 3 + c]);
    m[3 + c] = 0.5f * (d[i * 3 + c] + d[j * 3 + c]);
    m[6 + c] = 0.5f * (r[i * rs + (rs == 3 ? c : 0)] + r[j * rs + (rs == 3 ? c : 0)]);
  }
}

TruthPairEval ahd_image_pair_eval(const AhdImage& a, double dz_min) {
  return [&a, dz_min](size_t i, size_t j, const double n[3], double out[3]) {
    float m[9];
    truth_mid_planes(a.iz.data(), a.d.data(), a.ratio.data(), i, j, a.one_ratio ? 1 : 3, m);
    decode_irradiance(m, m + 3, m + 6, n, dz_min, out);
  };
}

AhdImage searched_direction_fit(const ShImage& sh, const FitOptions& opt, int count) {
  AhdImage a = make_ahd_image(sh.width, sh.height, opt.ratio_form == RatioForm::Luminance);
  a.coverage = sh.coverage;
  FitOptions ls = opt;
  ls.direction_fit = DirectionFit::Refined;  // fit_colours' least-squares luminance ratio
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (size_t i = 0; i < sh.texels(); ++i) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    AhdFit best = fit_texel(p, opt);
    if (sh.coverage[i]) {
      double best_err = 1e300;
      for (int j = 0; j < count; ++j) {
        const double z = 1.0 - (j + 0.5) / count, r = std::sqrt(1.0 - z * z);
        double d[3] = {r * std::cos(golden * j), r * std::sin(golden * j), z};
        tilt_above_horizon(d, opt.dz_min);
        const double zz[3] = {0, 0, 1};
        double iz[3];
        for (int c = 0; c < 3; ++c) iz[c] = std::max(0.0, eval_irradiance(p[c], zz));
        const AhdFit f = fit_colours(p, d, iz, ls);
        double err = 0;
        for (int c = 0; c < 3; ++c) err += hemisphere_mse(hemisphere_moments(p[c], d), fitted_ca(f, c), fitted_cd(f, c));
        if (err < best_err) best_err = err, best = f;
      }
    }
    a.set_texel(i, best);
  }
  return a;
}

}  // namespace ahd

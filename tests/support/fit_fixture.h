// What the fit's tests share (tests/unit and tests/accuracy fit_test.cpp): random SH, reference
// moments by quadrature, the constraint checks.
#pragma once
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <random>
#include "fit/ahd_decode.h"
#include "fit/ahd_fit.h"
#include "fit/fit_image.h"
#include "image/sh_exr.h"
#include "lab/hard_cases.h"
#include "sanitized.h"

namespace ahd_fixture::fit_fixture {

using namespace ::ahd;

// Random valid SH: 1–4 directional lights anywhere on the sphere plus ambient, random colours,
// over five decades of brightness. L1 or L2.
inline void random_texel(std::mt19937& rng, int coeffs, float* sh) {
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  std::fill(sh, sh + coeffs * 3, 0.0f);
  const double scale = std::pow(10.0, u(rng) * 5 - 2);
  const int lights = 1 + int(u(rng) * 4);
  for (int l = 0; l < lights; ++l) {
    double d[3] = {g(rng), g(rng), g(rng)};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double& v : d) v /= len;
    const double rgb[3] = {scale * u(rng), scale * u(rng), scale * u(rng)};
    add_directional_light(sh, coeffs, d, rgb);
  }
  const double amb[3] = {scale * 0.1 * u(rng), scale * 0.1 * u(rng), scale * 0.1 * u(rng)};
  add_ambient(sh, amb);
}

inline void polys_of(const float* sh, int coeffs, IrradiancePoly p[3]) {
  for (int c = 0; c < 3; ++c) p[c] = irradiance_poly(sh + c, coeffs, 3);
}

// Hemisphere quadrature independent of the lune formulas: θ from z, φ around z, Gauss–Legendre
// on pieces split at the kink of max(0, ω·d), so the integrand is smooth on every piece.
struct Quadrature {
  std::vector<double> w, dir;  // weights, directions
};

inline void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& wt) {
  x.resize(size_t(n));
  wt.resize(size_t(n));
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 0;
    for (int it = 0; it < 100; ++it) {
      double p1 = 1, p2 = 0;
      for (int j = 0; j < n; ++j) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2 * j + 1) * z * p2 - j * p3) / (j + 1);
      }
      pp = n * (z * p1 - p2) / (z * z - 1);
      const double z1 = z;
      z = z1 - p1 / pp;
      if (std::fabs(z - z1) < 1e-15) break;
    }
    x[size_t(i)] = z;
    wt[size_t(i)] = 2 / ((1 - z * z) * pp * pp);
  }
}

inline Quadrature hemisphere_quadrature(const double d[3]) {
  std::vector<double> gx, gw;
  gauss_legendre(16, gx, gw);
  const double phid = std::atan2(d[1], d[0]);
  std::vector<double> cuts = {0, 2 * kPi};
  for (double c : {phid + kPi / 2, phid - kPi / 2}) {
    c = std::fmod(c + 4 * kPi, 2 * kPi);
    if (c > 0 && c < 2 * kPi) cuts.push_back(c);
  }
  std::sort(cuts.begin(), cuts.end());
  // Near a cut the kink's θ moves fast in φ (over a width ~ d_z): grade the φ subintervals
  // geometrically towards both ends of every piece.
  std::vector<double> phis;
  for (size_t s = 0; s + 1 < cuts.size(); ++s) {
    const double a = cuts[s], b = cuts[s + 1], half = 0.5 * (b - a);
    std::vector<double> pts = {a, b, a + half};
    for (int j = 1; j <= 18; ++j) {
      pts.push_back(a + half * std::ldexp(1.0, -j));
      pts.push_back(b - half * std::ldexp(1.0, -j));
    }
    std::sort(pts.begin(), pts.end());
    for (double p : pts) phis.push_back(p);
  }
  Quadrature q;
  const double rxy = std::hypot(d[0], d[1]);
  for (size_t s = 0; s + 1 < phis.size(); ++s) {
    const double a = phis[s], b = phis[s + 1];
    if (b <= a) continue;
    for (size_t i = 0; i < gx.size(); ++i) {
      const double ph = 0.5 * (a + b) + 0.5 * (b - a) * gx[i];
      const double wph = 0.5 * (b - a) * gw[i];
      // Kink in θ where sinθ·rxy·cos(φ−φd) + cosθ·d_z = 0.
      std::vector<double> tc = {0, kPi / 2};
      const double k = rxy * std::cos(ph - phid);
      const double th = std::atan2(-d[2], k);
      for (double t : {th, th + kPi, th - kPi})
        if (t > 0 && t < kPi / 2) tc.push_back(t);
      std::sort(tc.begin(), tc.end());
      for (size_t r = 0; r + 1 < tc.size(); ++r) {
        const double ta = tc[r], tb = tc[r + 1];
        for (size_t j = 0; j < gx.size(); ++j) {
          const double t = 0.5 * (ta + tb) + 0.5 * (tb - ta) * gx[j];
          const double wt = 0.5 * (tb - ta) * gw[j] * std::sin(t) * wph;
          q.w.push_back(wt);
          q.dir.push_back(std::sin(t) * std::cos(ph));
          q.dir.push_back(std::sin(t) * std::sin(ph));
          q.dir.push_back(std::cos(t));
        }
      }
    }
  }
  return q;
}

}  // namespace ahd_fixture::fit_fixture

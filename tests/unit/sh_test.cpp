// SH math: the irradiance polynomial against direct numerical convolution, rotation, frames.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sh/sh.h"
#include "lab/hard_cases.h"

using namespace ahd;

namespace {

// E(n) = ∫ L(ω) max(0, n·ω) dω by brute-force quadrature of the SH radiance (independent of the
// closed-form Â_l convolution in irradiance_poly).
double irradiance_by_quadrature(const float* sh, int coeffs, const double n[3]) {
  const int nt = 400, np = 800;
  double sum = 0;
  for (int it = 0; it < nt; ++it) {
    const double ct = 1.0 - 2.0 * (it + 0.5) / nt;
    const double st = std::sqrt(1 - ct * ct);
    for (int ip = 0; ip < np; ++ip) {
      const double ph = 2 * kPi * (ip + 0.5) / np;
      const double w[3] = {st * std::cos(ph), st * std::sin(ph), ct};
      const double c = w[0] * n[0] + w[1] * n[1] + w[2] * n[2];
      if (c <= 0) continue;
      double y[9];
      sh_basis(w[0], w[1], w[2], coeffs, y);
      double L = 0;
      for (int k = 0; k < coeffs; ++k) L += sh[k * 3] * y[k];
      sum += L * c;
    }
  }
  return sum * 4 * kPi / (nt * np);
}

}  // namespace

TEST(Sh, IrradiancePolyMatchesQuadratureL1AndL2) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int coeffs : {4, 9}) {
    float sh[27];
    for (float& v : sh) v = u(rng);
    sh[0] = 3.0f;
    const IrradiancePoly p = irradiance_poly(sh, coeffs, 3);
    const double ns[3][3] = {{0, 0, 1}, {0.6, 0, 0.8}, {-0.48, 0.64, -0.6}};
    for (const auto& n : ns) {
      const double a = eval_irradiance(p, n), b = irradiance_by_quadrature(sh, coeffs, n);
      EXPECT_NEAR(a, b, 2e-3 * std::fabs(b) + 2e-3) << "coeffs " << coeffs;
    }
  }
}

TEST(Sh, DirectionalLightIrradianceIsClampedCosineAtL1) {
  // A delta light of irradiance 1 from d: its L1 projection gives E(n) = 1/4 + (1/2) n·d.
  float sh[27] = {};
  const double d[3] = {0.0, 0.6, 0.8}, one[3] = {1, 1, 1};
  add_directional_light(sh, 4, d, one);
  const IrradiancePoly p = irradiance_poly(sh, 4, 3);
  EXPECT_NEAR(p.e0, 0.25, 1e-6);
  EXPECT_NEAR(p.e[1], 0.5 * 0.6, 1e-6);
  EXPECT_NEAR(p.e[2], 0.5 * 0.8, 1e-6);
}

TEST(Sh, RotationPreservesValues) {
  float sh[27];
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  for (float& v : sh) v = u(rng);
  const IrradiancePoly p = irradiance_poly(sh, 9, 3);
  const double n[3] = {0.36, -0.48, 0.8};
  double R[3][3];
  frame_from_normal(n, R);
  const IrradiancePoly q = rotate_poly(p, R);
  const double w[3] = {0.1, 0.7, -0.70710678};
  double wl[3];  // w in the new frame
  for (int i = 0; i < 3; ++i) wl[i] = R[i][0] * w[0] + R[i][1] * w[1] + R[i][2] * w[2];
  EXPECT_NEAR(eval_irradiance(p, w), eval_irradiance(q, wl), 1e-12);
  // The frame's z is the normal: E along the normal becomes E(z) in the local frame.
  const double z[3] = {0, 0, 1};
  EXPECT_NEAR(eval_irradiance(p, n), eval_irradiance(q, z), 1e-12);
}

TEST(Sh, FrameIsOrthonormalRightHanded) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  for (int k = 0; k < 1000; ++k) {
    double n[3] = {g(rng), g(rng), g(rng)};
    if (k == 0) n[0] = 0, n[1] = 0, n[2] = -1;  // the pole the construction must still handle
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& v : n) v /= len;
    double R[3][3];
    frame_from_normal(n, R);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double dot = R[i][0] * R[j][0] + R[i][1] * R[j][1] + R[i][2] * R[j][2];
        ASSERT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-12);
      }
    // t × b = n
    const double cx = R[0][1] * R[1][2] - R[0][2] * R[1][1];
    const double cy = R[0][2] * R[1][0] - R[0][0] * R[1][2];
    const double cz = R[0][0] * R[1][1] - R[0][1] * R[1][0];
    ASSERT_NEAR(cx, n[0], 1e-12);
    ASSERT_NEAR(cy, n[1], 1e-12);
    ASSERT_NEAR(cz, n[2], 1e-12);
  }
}

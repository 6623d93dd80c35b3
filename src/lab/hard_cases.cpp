#include "lab/hard_cases.h"

#include <cmath>
#include <limits>

namespace ahd {

void add_directional_light(float* t, int coeffs, const double d[3], const double rgb[3]) {
  double y[9];
  sh_basis(d[0], d[1], d[2], coeffs, y);
  for (int k = 0; k < coeffs; ++k)
    for (int c = 0; c < 3; ++c) t[k * 3 + c] += float(rgb[c] * y[k]);
}

void add_ambient(float* t, const double rgb[3]) {
  // Constant radiance L projects onto Y00 only: L · 4π · Y00.
  for (int c = 0; c < 3; ++c) t[c] += float(rgb[c] * 4.0 * kPi * kY00);
}

namespace {

ShImage row(int n) { return make_sh_image(n, 1, 9); }

}  // namespace

std::vector<HardCase> hard_cases() {
  std::vector<HardCase> cases;
  const double white[3] = {1, 1, 1};
  {
    cases.push_back({"black texels", row(4)});
  }
  {
    HardCase c{"pure ambient (L1 = 0)", row(3)};
    const double a[3] = {0.3, 0.5, 0.7}, b[3] = {1e-3, 1e-3, 1e-3}, h[3] = {100, 80, 60};
    add_ambient(c.sh.texel(0), a);
    add_ambient(c.sh.texel(1), b);
    add_ambient(c.sh.texel(2), h);
    cases.push_back(std::move(c));
  }
  {
    // One directional light swept from the normal (d_z = 1) through the horizon to straight
    // below (d_z = −1), including d_z = 1e-4, plus a little ambient.
    const double dz[] = {1.0, 0.9, 0.7, 0.5, 0.3, 0.2, 0.1, 0.05, 0.02, 1e-2, 1e-3, 1e-4, 0.0, -1e-4, -0.1, -0.5, -0.9, -1.0};
    const int n = int(std::size(dz));
    HardCase c{"directional light swept normal → horizon → below", row(n)};
    for (int i = 0; i < n; ++i) {
      const double s = std::sqrt(std::max(0.0, 1.0 - dz[i] * dz[i]));
      const double d[3] = {s, 0, dz[i]};
      add_directional_light(c.sh.texel(size_t(i)), 9, d, white);
      const double amb[3] = {0.02, 0.02, 0.02};
      add_ambient(c.sh.texel(size_t(i)), amb);
    }
    cases.push_back(std::move(c));
  }
  {
    HardCase c{"two opposed lights cancelling L1", row(2)};
    const double d1[3] = {0.6, 0, 0.8}, d2[3] = {-0.6, 0, 0.8};
    add_directional_light(c.sh.texel(0), 9, d1, white);
    add_directional_light(c.sh.texel(0), 9, d2, white);
    const double e1[3] = {1, 0, 0}, e2[3] = {-1, 0, 0};
    add_directional_light(c.sh.texel(1), 9, e1, white);
    add_directional_light(c.sh.texel(1), 9, e2, white);
    cases.push_back(std::move(c));
  }
  {
    // Ringing: a strong grazing light projected to L2 gives negative irradiance on the far side,
    // and hand-made coefficients give a negative I_z outright.
    HardCase c{"negative SH from ringing", row(3)};
    const double d[3] = {0, 0, -1};
    add_directional_light(c.sh.texel(0), 9, d, white);  // light from straight below: I_z < 0 at L2
    float* t = c.sh.texel(1);
    t[0] = 0.1f, t[1] = 0.1f, t[2] = 0.1f;
    t[2 * 3 + 0] = -1.0f, t[2 * 3 + 1] = -1.0f, t[2 * 3 + 2] = -1.0f;  // L1 z strongly negative
    float* u = c.sh.texel(2);
    u[0] = 1.0f, u[1] = 1.0f, u[2] = 1.0f;
    u[6 * 3 + 0] = -3.0f, u[6 * 3 + 1] = -3.0f, u[6 * 3 + 2] = -3.0f;  // L2 zonal ringing
    cases.push_back(std::move(c));
  }
  {
    HardCase c{"NaN, ±Inf, −0 and denormals in the input", row(5)};
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    c.sh.texel(0)[0] = nan;
    c.sh.texel(1)[4] = inf;
    c.sh.texel(2)[5] = -inf;
    for (int k = 0; k < 27; ++k) c.sh.texel(3)[k] = -0.0f;
    for (int k = 0; k < 27; ++k) c.sh.texel(4)[k] = std::numeric_limits<float>::denorm_min() * float(k + 1);
    cases.push_back(std::move(c));
  }
  {
    const double scales[] = {1e-8, 1e-4, 1.0, 1e3, 6e4, 65504.0, 1e5, 1e7};
    const int n = int(std::size(scales));
    HardCase c{"values from 1e-8 to beyond half max (65504)", row(n)};
    for (int i = 0; i < n; ++i) {
      const double d[3] = {0.5, 0.3, 0.81240384};
      const double rgb[3] = {scales[i], scales[i] * 0.8, scales[i] * 0.6};
      add_directional_light(c.sh.texel(size_t(i)), 9, d, rgb);
      const double amb[3] = {scales[i] * 0.05, scales[i] * 0.05, scales[i] * 0.05};
      add_ambient(c.sh.texel(size_t(i)), amb);
    }
    cases.push_back(std::move(c));
  }
  {
    HardCase c{"a single colour channel lit", row(3)};
    for (int ch = 0; ch < 3; ++ch) {
      const double d[3] = {0.3, -0.4, 0.866};
      double rgb[3] = {0, 0, 0};
      rgb[ch] = 2.0;
      add_directional_light(c.sh.texel(size_t(ch)), 9, d, rgb);
    }
    cases.push_back(std::move(c));
  }
  {
    // L2 dominating L1: lights from opposite sides at equal elevation (L1 cancels, L2 remains),
    // and a ring of lights at the horizon.
    HardCase c{"L2 terms dominating L1", row(2)};
    const double d1[3] = {0.7, 0, 0.714}, d2[3] = {-0.7, 0, 0.714};
    add_directional_light(c.sh.texel(0), 9, d1, white);
    add_directional_light(c.sh.texel(0), 9, d2, white);
    const double small[3] = {0.01, 0.01, 0.01};
    const double d3[3] = {0.0, 0.6, 0.8};
    add_directional_light(c.sh.texel(0), 9, d3, small);
    for (int k = 0; k < 8; ++k) {
      const double a = k * kPi / 4;
      const double d[3] = {std::cos(a), std::sin(a), 0.05};
      add_directional_light(c.sh.texel(1), 9, d, white);
    }
    cases.push_back(std::move(c));
  }
  return cases;
}

}  // namespace ahd

#include <random>

namespace ahd {

ShImage grazing_light_set(int n, uint32_t seed) {
  ShImage img = make_sh_image(n, n, 9);
  std::mt19937 rng(seed);
  auto unit = [&]() { return double(rng() >> 8) * (1.0 / 16777216.0); };
  for (size_t i = 0; i < img.texels(); ++i) {
    const double elev = (-10.0 + 100.0 * (double(i) + 0.5) / double(img.texels())) * kPi / 180.0;
    const double az = 2 * kPi * unit();
    const double d[3] = {std::cos(elev) * std::cos(az), std::cos(elev) * std::sin(az), std::sin(elev)};
    const double rgb[3] = {0.5 + unit(), 0.5 + unit(), 0.5 + unit()};
    add_directional_light(img.texel(i), 9, d, rgb);
    const double a = std::pow(10.0, -3.0 + 2.5 * unit());
    const double amb[3] = {a, a, a};
    add_ambient(img.texel(i), amb);
  }
  return img;
}

}  // namespace ahd

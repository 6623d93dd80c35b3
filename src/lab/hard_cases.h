// The hard-case set: SH texels every real bake eventually contains, as named data. Used by the
// tests (each case asserts finite output and the constraints) and by `ahdpack report hard-cases`
// (docs/accuracy.md "Hard cases").
#pragma once
#include <string>
#include <vector>

#include "sh/sh_image.h"

namespace ahd {

struct HardCase {
  std::string name;
  ShImage sh;  // a small tangent-space L2 image (1×N texels) holding the case
};

// Every case, deterministic. Non-finite cases hold NaN/Inf coefficients as a reader would see them
// (before sanitisation).
std::vector<HardCase> hard_cases();

// Adds the radiance-SH of a directional (delta) light of irradiance `rgb` from unit direction d.
void add_directional_light(float* sh_texel, int coeffs, const double d[3], const double rgb[3]);

// Adds constant radiance (ambient) over the whole sphere.
void add_ambient(float* sh_texel, const double rgb[3]);

}  // namespace ahd

namespace ahd {

// n×n texels, each lit by one directional light at an elevation spread uniformly from the
// horizon-below (−10°) to the normal (90°), random azimuth and colour, plus ambient from 0.1 % to
// 30 % of the light. The set that decides the horizon rule's eps (`ahdpack report eps`).
ShImage grazing_light_set(int n, uint32_t seed);

}  // namespace ahd

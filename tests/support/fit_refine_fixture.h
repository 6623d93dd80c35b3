// What the refined fit's tests share (tests/unit and tests/accuracy fit_refine_test.cpp): the
// scenes and the per-texel fit options of issue 18.
#pragma once
#include <algorithm>
#include <cstdint>

#include "fit/ahd_fit.h"
#include "lab/fit_quality.h"
#include "sample/analytic_baker.h"
#include "sh/sh_image.h"

namespace ahd::fit_refine_fixture {
// Issue 18's refined fit, each texel's d chosen on its own SH (direction_window 0), with its pair
// guard at 4° (off by default since issue 43, still an option): what these tests pin down. The
// windowed fit (issue 27) has its own tests (FitWindow.*).
inline FitOptions options(RatioForm form, DirectionFit dir) {
  FitOptions o;
  o.ratio_form = form;
  o.direction_fit = dir;
  o.direction_window = 0;
  o.pair_guard_deg = 4.0;
  return o;
}

// The canonical analytic scene (the harder scene of the first round).
inline ShImage smooth_scene() {
  BakerOptions bo;
  bo.width = bo.height = 64;
  return bake_analytic_scene(bo);
}

// Issue 18's "smooth scene", calibrated to its "today" column (fit_quality.h).
inline ShImage calibrated_smooth_scene() {
  BakerOptions bo;
  bo.width = bo.height = 64;
  bo.coeffs = kSmoothCoeffs;
  bo.point_scale = kSmoothPointScale, bo.sky_scale = kSmoothSkyScale;
  bo.ceiling_scale = kSmoothCeilingScale, bo.bounce_scale = kSmoothBounceScale;
  return bake_analytic_scene(bo);
}

inline ShImage calibrated_random_set(int n, uint32_t seed) {
  return random_lighting_set(n, seed, kCalibratedSaturation, kCalibratedAmbient);
}

inline void polys_and_iz(const ShImage& sh, size_t i, IrradiancePoly p[3], double iz[3]) {
  local_polys(sh, i, p);
  for (int c = 0; c < 3; ++c) iz[c] = std::max(0.0, p[c].e0 + p[c].e[2] + p[c].q[2][2]);
}

// A smooth lit scene with Monte-Carlo-like noise: the case the window is for.
inline ShImage noisy_scene() {
  ShImage sh = calibrated_smooth_scene();
  uint32_t state = 12345;
  for (float& v : sh.data) {
    state = state * 1664525u + 1013904223u;
    v *= 1.0f + 0.3f * (float(state >> 8) / float(1u << 24) - 0.5f);
  }
  return sh;
}

}  // namespace ahd::fit_refine_fixture

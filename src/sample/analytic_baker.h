// A small deterministic "analytic baker": the built-in sample lightmap and the test-data generator.
//
// Scene (world space, y up): a floor (y = 0) and a back wall (z = 0), each one chart of the atlas
// (floor left, wall right, empty gutters around them). Lights: a point light (hard shadow), a
// ceiling area light (soft shadow), a warm-red area light beside the scene standing in for
// coloured bounce, and a blue sky dome. One sphere occludes the point and area lights. The
// incident radiance at each texel centre is projected onto the canonical SH in the texel's
// tangent frame. No path tracing: only what such a scene needs.
#pragma once
#include <cstdint>

#include "sh/sh_image.h"

namespace ahd {

struct BakerOptions {
  int width = 256;
  int height = 256;
  int coeffs = 9;       // 4 (L1) or 9 (L2)
  uint32_t seed = 0;    // 0 = the canonical scene; other seeds move and recolour the lights
  int area_samples = 8; // per side of each area light (stratified, deterministic)
  int threads = 0;
  // Softer variants (issue 18's "smooth scene"): the point light's intensity (hard shadow), the
  // sky's radiance (ambient), the ceiling area light's and the coloured bounce light's radiance are
  // scaled by these (0 removes a light). All 1 = the canonical scene.
  double point_scale = 1.0;
  double sky_scale = 1.0;
  double ceiling_scale = 1.0;
  double bounce_scale = 1.0;
};

// Bakes the scene; coverage marks the two charts. Sizes 1×1 to 4096² (and beyond) are accepted.
ShImage bake_analytic_scene(const BakerOptions& opt);

}  // namespace ahd

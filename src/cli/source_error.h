// `verify --source`'s figures: a conversion's level 0 against its source SH, with relative errors
// whose denominator is floored at a fraction of the image's own scale, so that near-black texels
// cannot dominate them (docs/tools.md "Verify in CI").
//
// Why a floor: the report's `relative` figure divides each texel's error by that texel's own
// irradiance. Real bakes are mostly dark: in the Godot 4.2 vermilion bake 54 % of the covered
// texels are below 1 % of the p99 irradiance and 27 % below E = 0.001. There, half-float and BC6H
// steps, the fit's clamps and the SH's own ringing are large relative to almost nothing and
// invisible once the scene is exposed for its lit parts; the per-texel relative p99 is then the
// p99 of noise over black (0.645 on a faithful pc-bc conversion of vermilion, 0.607 for the
// unquantised fit alone). Measured against max(E, floor × p99(E)), a texel at or above the floor
// keeps its relative error, and a darker one is judged by its absolute error in units of the image's
// bright end.
//
// Why the reference is E clamped at 0: truncated SH rings below zero in directions away from a
// strong light; no non-negative decode (AHD's lobe, or the baker's own engine after its clamp) can
// follow it there, and a renderer shows it as black.
#pragma once
#include <cstddef>

#include "pipeline/plane_decode.h"
#include "sh/sh_image.h"

namespace ahd::cli {

// The default floor, 3 % of the p99: an sRGB display exposed so that the p99 is white shows 3 % at
// ≈ 19 % of its range (48/255). On vermilion (1 page, 512²) a fresh pc-bc conversion then measures
// rel-p99 0.228 and iz-rel-p99 0.029 (uncompressed: 0.228, 0.00044) against the bounds 0.30 and 0.05;
// floor 0.01 gives 0.291, floor 0 (the report's figure with E clamped) 0.5.
constexpr double kDefaultDarkFloor = 0.03;

struct SourceErrorFigures {
  size_t texels = 0;      // covered texels measured
  double scale = 0;       // p99 over texels of the mean luminance of max(0, E) over the hemisphere
  double iz_scale = 0;    // p99 over texels of the luminance of max(0, E) along the normal
  double rel_p99 = 0;     // p99 of RMSE over 64 hemisphere normals and channels / max(mean lum. E, floor × scale)
  double log_rmse = 0;    // mean over texels of the log2(1+E) RMSE over the hemisphere (the report's log2 figure)
  double iz_rel_p99 = 0;  // p99 of |I(z) − E(z)| (largest channel) / max(lum. E(z), floor × iz_scale)
  size_t floored = 0;     // texels whose hemisphere denominator is the floor
};

// The figures of level 0 of one page (`level0` in units of E, cli/conversion_view.h) against the
// page's source SH over its covered texels. `floor` ≥ 0 (0: the plain per-texel relative errors).
// Deterministic at any thread count; safe on any decoded planes of the source's size.
SourceErrorFigures measure_against_source(const ShImage& sh, const DecodedPlanes& level0, double dz_min, double floor);

}  // namespace ahd::cli

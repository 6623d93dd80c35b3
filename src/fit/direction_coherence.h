// Coherence of the refined directions across the image (issue 18): a per-texel optimum can turn
// faster across a scene than the linear d, or jump where two directions are nearly as good, and
// bilinear filtering and mips then blend unrelated lobes.
#pragma once
#include "fit/fit_image.h"

namespace ahd {

// A second pass over a refined fit: for every covered, directional texel, the mean of the first
// pass's d over its covered 3×3 neighbourhood (normalised, horizon rule) replaces the texel's d when
// its constrained error is within opt.coherence_tolerance (relative) of the texel's own refined
// error and no worse than the linear d's; the colours are then refitted there (fit_colours). Reads
// only the first pass's output, so the result does not depend on `threads`. Constraints hold as
// for any d (I_z exact, C ≥ 0, d_z ≥ dz_min).
// `linear_value` (null, or one float a texel): the first pass's objective at each texel's linear d
// (fit_texels' linear_value) rounded to float. The comparison with it is decided from that float
// where the float's neighbours bracket the exact value clear of the mean's; elsewhere (and without
// it) the linear d's objective is computed again. The same bytes either way.
void smooth_directions(const ShImage& sh, const FitOptions& opt, int threads, AhdImage* fit,
                       const float* linear_value = nullptr);

}  // namespace ahd

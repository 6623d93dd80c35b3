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
void smooth_directions(const ShImage& sh, const FitOptions& opt, int threads, AhdImage* fit);

}  // namespace ahd

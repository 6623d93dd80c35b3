// The SH a refined fit chooses its direction on (issue 27): each covered texel's SH averaged with
// its covered neighbours' in a (2r+1)² window. On a Monte-Carlo baked lightmap the per-texel SH
// carries the bake's noise, and the direction that best fits one texel's noise is not the one that
// best fits the light: choosing d on the window's mean and solving the colours on the texel's own
// SH keeps I_z exact and the colours non-negative while the direction follows the light
// (docs/accuracy-real-lighting.md: error and neighbour angles on path-traced scenes).
// Charts are separated by gutters (uncovered texels) in every baker's atlas, so a window of radius 1
// does not reach across one; where charts touch, only their edge texels mix.
#pragma once
#include <cstddef>

#include "sh/sh.h"
#include "sh/sh_image.h"

namespace ahd {

// The three channel polynomials of texel i's window mean, in texel i's local frame: the covered
// texels of the window (texel i counts even when uncovered) averaged coefficient by coefficient —
// world-space SH before the rotation into texel i's normal frame, so every neighbour is averaged
// in the one frame its SH is stored in. radius 0 gives local_polys(sh, i, out) exactly.
void window_local_polys(const ShImage& sh, size_t i, int radius, IrradiancePoly out[3]);

}  // namespace ahd

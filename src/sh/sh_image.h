// The canonical SH lightmap every reader produces and every later stage consumes (the struct is
// public: <ahd/types.h>).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include <ahd/types.h>

namespace ahd {

// Allocates a zeroed image with every texel covered.
ShImage make_sh_image(int width, int height, int coeffs);

}  // namespace ahd

#include "sh/sh.h"

namespace ahd {

// The three channel irradiance polynomials of texel i in its LOCAL frame (z = surface normal):
// as stored for tangent-space images, rotated by frame_from_normal(n) for world-space ones.
void local_polys(const ShImage& img, size_t i, IrradiancePoly out[3]);

}  // namespace ahd

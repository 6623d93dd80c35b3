// The canonical SH lightmap every reader produces and every later stage consumes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ahd {

// w×h texels of `coeffs` (4 = L1, 9 = L2) radiance-SH coefficients × RGB, canonical order and
// normalisation (sh/sh.h). Layout: data[((y*w + x)*coeffs + k)*3 + c].
struct ShImage {
  int width = 0;
  int height = 0;
  int coeffs = 9;
  std::vector<float> data;
  // 1 where a chart covers the texel, 0 in gutters / empty space. Always width*height entries.
  std::vector<uint8_t> coverage;
  // Empty: the SH is in tangent space (z = surface normal). Otherwise width*height*3 unit WORLD-space
  // normals, and the SH is in world space; the fit rotates it into frame_from_normal(n).
  std::vector<float> normals;

  size_t texels() const { return size_t(width) * height; }
  float* texel(size_t i) { return data.data() + i * size_t(coeffs) * 3; }
  const float* texel(size_t i) const { return data.data() + i * size_t(coeffs) * 3; }
};

// Allocates a zeroed image with every texel covered.
ShImage make_sh_image(int width, int height, int coeffs);

}  // namespace ahd

#include "sh/sh.h"

namespace ahd {

// The three channel irradiance polynomials of texel i in its LOCAL frame (z = surface normal):
// as stored for tangent-space images, rotated by frame_from_normal(n) for world-space ones.
void local_polys(const ShImage& img, size_t i, IrradiancePoly out[3]);

}  // namespace ahd

#include "sh/sh_image.h"

#include "core/error.h"
#include "core/large_buffer.h"

namespace ahd {

ShImage make_sh_image(int width, int height, int coeffs) {
  if (width <= 0 || height <= 0) throw Error("SH image size must be positive");
  if (!valid_sh_coeffs(coeffs)) throw Error("SH images hold 1 (L0), 4 (L1) or 9 (L2) coefficients");
  ShImage img;
  img.width = width;
  img.height = height;
  img.coeffs = coeffs;
  assign_large(img.data, size_t(width) * height * coeffs * 3, 0.0f);
  assign_large(img.coverage, size_t(width) * height, uint8_t(1));
  return img;
}

}  // namespace ahd

namespace ahd {

void local_polys(const ShImage& img, size_t i, IrradiancePoly out[3]) {
  const float* t = img.texel(i);
  for (int c = 0; c < 3; ++c) out[c] = irradiance_poly(t + c, img.coeffs, 3);
  if (img.normals.empty()) return;
  const float* nf = img.normals.data() + i * 3;
  const double n[3] = {nf[0], nf[1], nf[2]};
  double R[3][3];
  frame_from_normal(n, R);
  for (int c = 0; c < 3; ++c) out[c] = rotate_poly(out[c], R);
}

}  // namespace ahd

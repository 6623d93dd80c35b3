#include "fit/direction_filter.h"

namespace ahd {

void window_local_polys(const ShImage& sh, size_t i, int radius, IrradiancePoly out[3]) {
  if (radius <= 0) return local_polys(sh, i, out);
  const int n = sh.coeffs * 3;
  double sum[kShCoeffsL2 * 3] = {};
  int count = 0;
  const int x = int(i % size_t(sh.width)), y = int(i / size_t(sh.width));
  for (int yy = y - radius; yy <= y + radius; ++yy) {
    if (yy < 0 || yy >= sh.height) continue;
    for (int xx = x - radius; xx <= x + radius; ++xx) {
      if (xx < 0 || xx >= sh.width) continue;
      const size_t j = size_t(yy) * size_t(sh.width) + size_t(xx);
      if (j != i && !sh.coverage[j]) continue;
      const float* t = sh.texel(j);
      for (int k = 0; k < n; ++k) sum[k] += t[k];
      ++count;
    }
  }
  float mean[kShCoeffsL2 * 3];
  for (int k = 0; k < n; ++k) mean[k] = float(sum[k] / count);
  for (int c = 0; c < 3; ++c) out[c] = irradiance_poly(mean + c, sh.coeffs, 3);
  if (sh.normals.empty()) return;
  const float* nf = sh.normals.data() + i * 3;
  const double nd[3] = {nf[0], nf[1], nf[2]};
  double R[3][3];
  frame_from_normal(nd, R);
  for (int c = 0; c < 3; ++c) out[c] = rotate_poly(out[c], R);
}

}  // namespace ahd

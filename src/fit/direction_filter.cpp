#include "fit/direction_filter.h"

#include <algorithm>

namespace ahd {

namespace {

// The window's sums, coefficient by coefficient, in the order of the generic loop (rows, then
// columns; each sum[k] is its own chain, so a compiler may vectorise across k without changing a
// bit). N: the coefficient count (27 for L2, 12 for L1; 0: sh.coeffs × 3 at run time, the generic
// loop), a compile-time bound so the inner loop unrolls (window_local_polys was 1 600 instructions a
// texel in the generic form, docs/fit.md "The windowed fit's cost").
template <int N>
int window_sums(const ShImage& sh, size_t i, int radius, double* sum) {
  const int n = N ? N : sh.coeffs * 3;
  int count = 0;
  const int x = int(i % size_t(sh.width)), y = int(i / size_t(sh.width));
  const int y0 = std::max(0, y - radius), y1 = std::min(sh.height - 1, y + radius);
  const int x0 = std::max(0, x - radius), x1 = std::min(sh.width - 1, x + radius);
  for (int yy = y0; yy <= y1; ++yy) {
    for (int xx = x0; xx <= x1; ++xx) {
      const size_t j = size_t(yy) * size_t(sh.width) + size_t(xx);
      if (j != i && !sh.coverage[j]) continue;
      const float* t = sh.texel(j);
      if constexpr (N > 0) {
        for (int k = 0; k < N; ++k) sum[k] += t[k];
      } else {
        for (int k = 0; k < n; ++k) sum[k] += t[k];
      }
      ++count;
    }
  }
  return count;
}

}  // namespace

void window_local_polys(const ShImage& sh, size_t i, int radius, IrradiancePoly out[3]) {
  if (radius <= 0) return local_polys(sh, i, out);
  const int n = sh.coeffs * 3;
  double sum[kShCoeffsL2 * 3] = {};
  const int count = n == 27 ? window_sums<27>(sh, i, radius, sum)
                    : n == 12 ? window_sums<12>(sh, i, radius, sum)
                              : window_sums<0>(sh, i, radius, sum);
  float mean[kShCoeffsL2 * 3] = {};  // only the first n are read (zeroed: GCC 12 cannot see it)
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

// hemisphere_sums with AVX2: four directions at a time, each lane running the plain path's
// operations in its order (fit/hemisphere_sums.h), so the bits are the same.
#include "fit/hemisphere_sums.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include "fit/hemisphere_sums_x86.h"

namespace ahd {

using namespace hemisphere_x86;

AHD_AVX2 HemisphereSums hemisphere_sums_avx2(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n,
                                            bool with_log) {
  __m256d se = _mm256_setzero_pd(), sl = _mm256_setzero_pd(), lum = _mm256_setzero_pd();
  bool normal = true;
  const int full = n / 4 * 4;
  const bool l2 = has_l2(p);
  for (int k = 0; k < full; k += 4) add_group4(p, l, dirs + size_t(k) * 3, with_log, l2, se, sl, lum, &normal);
  return finish(p, l, dirs, full, n, with_log, normal, se, sl, lum);
}

}  // namespace ahd

#else

namespace ahd {
HemisphereSums hemisphere_sums_avx2(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n,
                                    bool with_log) {
  return hemisphere_sums_plain(p, l, dirs, n, with_log);
}
}  // namespace ahd

#endif

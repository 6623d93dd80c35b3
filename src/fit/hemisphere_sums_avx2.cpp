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
  for (int k = 0; k < full; k += 4) add_group4(p, l, dirs + size_t(k) * 3, with_log, se, sl, lum, &normal);
  // A ratio outside the normal doubles (std::log2's cases): the plain path, whose sums are the same.
  if (!normal) return hemisphere_sums_plain(p, l, dirs, n, with_log);
  alignas(32) double a[4], b[4], c[4];
  _mm256_store_pd(a, se);
  _mm256_store_pd(b, sl);
  _mm256_store_pd(c, lum);
  return finish(p, l, dirs, full, n, with_log, a, b, c);
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

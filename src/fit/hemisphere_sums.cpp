#include "fit/hemisphere_sums.h"

#include "core/cpu.h"

namespace ahd {

HemisphereSums hemisphere_sums_plain(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n,
                                     bool with_log) {
  double se[4] = {0, 0, 0, 0}, sl[4] = {0, 0, 0, 0}, lum[4] = {0, 0, 0, 0};
  for (int k = 0; k < n; ++k)
    add_direction(p, l, dirs + size_t(k) * 3, with_log, se[k & 3], sl[k & 3], lum[k & 3]);
  return combine_lanes(se, sl, lum);
}

HemisphereSums hemisphere_sums(const IrradiancePoly p[3], const AhdLobe& l, const double* dirs, int n, bool with_log) {
  if (n >= 8 && cpu::has(cpu::kAvx2 | cpu::kAvx512)) return hemisphere_sums_avx512(p, l, dirs, n, with_log);
  if (n >= 4 && cpu::has(cpu::kAvx2)) return hemisphere_sums_avx2(p, l, dirs, n, with_log);
  return hemisphere_sums_plain(p, l, dirs, n, with_log);
}

}  // namespace ahd

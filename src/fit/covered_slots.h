// Per-covered-texel arrays: each covered texel's slot, its rank among the covered texels in raster
// order (measure_error and the source-error figures keep one entry per covered texel).
#pragma once
#include <cstddef>
#include <vector>

#include "ahd/types.h"

namespace ahd {

// slot[i] = texel i's rank among sh's covered texels (0 where uncovered); `*covered` gets their
// count. sh.coverage must hold sh.texels() entries (check_sh_image). Pure; thread-safe.
inline std::vector<size_t> covered_slots(const ShImage& sh, size_t* covered) {
  const size_t n = sh.texels();
  std::vector<size_t> slot(n, 0);
  *covered = 0;
  for (size_t i = 0; i < n; ++i)
    if (sh.coverage[i]) slot[i] = (*covered)++;
  return slot;
}

}  // namespace ahd

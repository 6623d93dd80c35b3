// Bit-for-bit comparison of two fitted texels (every field, not the struct's padding).
#pragma once
#include <cstring>

#include "fit/ahd_fit.h"

namespace ahd {

inline bool same_fit_bits(const AhdFit& p, const AhdFit& q) {
  return std::memcmp(p.iz, q.iz, sizeof p.iz) == 0 && std::memcmp(p.d, q.d, sizeof p.d) == 0 &&
         std::memcmp(p.ratio, q.ratio, sizeof p.ratio) == 0 && p.flags == q.flags;
}

}  // namespace ahd

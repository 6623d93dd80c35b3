// The sizes of the direction and ratio planes of a profile with "dir_ratio_scale" s (issue 43): the
// planes are ceil(W/s) x ceil(H/s) with their own mip chain, as long as the I_z chain or as long as
// their size allows (the KTX2/Vulkan limit), so an I_z level past the end of theirs reads their last
// level (a GPU clamps the LOD the same way). One rule for the writer, decode and the manifest.
#pragma once
#include <algorithm>
#include <cstdint>

#include "core/pixel_format.h"

namespace ahd {

inline uint32_t scaled_plane_size(uint32_t n, int scale) { return (n + uint32_t(scale) - 1) / uint32_t(scale); }

// The levels of a w×h side plane beside an I_z chain of `levels` levels.
inline uint32_t scaled_plane_levels(uint32_t levels, uint32_t w, uint32_t h) {
  return std::min(levels, full_mip_count(w, h));
}

// The scale s ∈ {1, 2, 4} for which a pw×ph side plane beside a w×h I_z plane is
// (ceil(w/s), ceil(h/s)) — the smallest when several are — or 0 when there is none.
inline int side_plane_scale(uint32_t w, uint32_t h, uint32_t pw, uint32_t ph) {
  for (int s : {1, 2, 4})
    if (pw == scaled_plane_size(w, s) && ph == scaled_plane_size(h, s)) return s;
  return 0;
}

}  // namespace ahd

// Pure image functions of `ahdpack preview`: HDR planes to a fixed 8-bit log encoding (the page
// applies exposure on top), directions and ratios to colours, relative errors to a heat map.
#pragma once
#include <array>
#include <vector>

#include "core/image.h"

namespace ahd::cli {

// The fixed log encoding of HDR images for the page: code c ∈ [1/255, 1] holds
// x = white · 2^(kLogLo + c·(kLogHi − kLogLo)); code 0 is x ≤ white·2^kLogLo (black). 16 stops in
// 255 steps: 0.063 stop (4.4 %) per step, fine for looking, not for measuring.
inline constexpr double kLogLo = -14, kLogHi = 2;

// The p99 luminance of the texels with positive luminance (rgb: 3 floats per texel); 1 if none.
double white_point(const std::vector<float>& rgb);

// w×h×3 image of the log codes of `rgb` (3 floats per texel) relative to `white`.
ImageF log_encode(const std::vector<float>& rgb, int w, int h, double white);

// Unit directions (3 floats per texel, any length) as colours 0.5 + 0.5·normalise(d).
ImageF direction_colours(const std::vector<float>& d, int w, int h);

// Ratios in [0, 1] as they are (3 floats per texel; luminance form: all three equal).
ImageF ratio_image(const std::vector<float>& ratio, int w, int h);

// The heat map's colours from low to high (black → purple → red → orange → yellow → white): each
// stop brighter than the one before, so brighter always means a larger error.
const std::vector<std::array<float, 3>>& heat_stops();

// Relative errors (one per texel, NaN = not covered) on a log scale: 10^lo_exp → the first stop,
// 10^hi_exp → the last, clamped; uncovered texels dark blue-grey.
ImageF heat_map(const std::vector<float>& err, int w, int h, double lo_exp, double hi_exp);

}  // namespace ahd::cli

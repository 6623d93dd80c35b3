// The fit over a whole image: pure function, parallel over texels, deterministic.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fit/ahd_fit.h"
#include "sh/sh_image.h"

namespace ahd {

struct AhdImage {
  int width = 0;
  int height = 0;
  std::vector<AhdFit> texels;      // width*height
  std::vector<uint8_t> coverage;   // copied from the SH image
};

// How often each rule of the fit fired, over covered texels.
struct FitStats {
  size_t texels = 0;
  size_t covered = 0;
  size_t no_direction = 0;
  size_t dir_clamped = 0;
  size_t negative_iz = 0;
  size_t black = 0;
};

// One mip level after the fit stage: the SH it was fitted from and the fitted (dilated) AHD.
// The quantiser needs both: the closed loop refits the ratio against the SH.
struct FittedLevel {
  ShImage sh;
  AhdImage ahd;
};

// Fits every texel (uncovered ones too; their values are replaced by dilation later); a refined
// fit then takes the coherence pass (direction_coherence.h).
AhdImage fit_image(const ShImage& sh, const FitOptions& opt, int threads, FitStats* stats = nullptr);

}  // namespace ahd

// The fit over a whole image: pure function, parallel over texels, deterministic.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/image.h"
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
  AhdImage ahd;  // the fitted texels; empty in an ambient-only level
  ImageF iz;     // an ambient-only level's fit (an L0 image's: mips.h fit_ambient_level): I_z alone
};

// Texel i's fit, whichever form the level holds (ambient-only: d = z, ratio = 1, flags 0).
inline AhdFit fitted_texel(const FittedLevel& l, size_t i) {
  if (!l.ahd.texels.empty()) return l.ahd.texels[i];
  AhdFit f{};
  for (int c = 0; c < 3; ++c) {
    f.iz[c] = l.iz.data[i * 3 + size_t(c)];
    f.ratio[c] = 1.0f;
  }
  f.d[2] = 1.0f;
  return f;
}

// Fits every texel (uncovered ones too; their values are replaced by dilation later).
AhdImage fit_image(const ShImage& sh, const FitOptions& opt, int threads, FitStats* stats = nullptr);

// The fit of an L0 image (plain lightmaps: sh.coeffs == 1) as its I_z plane alone: every texel's
// fit is the pure ambient lobe (fit_texel_constant: d = z, ratio = 1), so the 3-channel plane holds
// bit for bit the iz that fit_image's texels would, in 12 bytes a texel instead of 40. stats as
// fit_image (every covered texel counts as "no direction"). Throws ahd::Error when sh.coeffs != 1.
ImageF fit_ambient_iz(const ShImage& sh, const FitOptions& opt, int threads, FitStats* stats = nullptr);

}  // namespace ahd

// The fit over a whole image: pure function, parallel over texels, deterministic.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fit/ahd_fit.h"
#include "sh/sh_image.h"

namespace ahd {

// The fitted texels of an image, stored as planes. Why planes and not an array of AhdFit: in the
// luminance form the three ratios are one number, and an AhdFit pads its flags byte to 4, so a
// texel takes 29 bytes here instead of 40 — at level 0 of a 1024² L1 lightmap that is 11 MiB of a
// peak that must stay within twice the 48 MiB of SH (docs/performance.md "Whole conversions").
struct AhdImage {
  int width = 0;
  int height = 0;
  bool one_ratio = false;          // the luminance form: ratio holds one value a texel, not three
  std::vector<float> iz;           // 3 a texel: irradiance along the normal, RGB
  std::vector<float> d;            // 3 a texel: unit direction, local frame
  std::vector<float> ratio;        // 1 (one_ratio) or 3 a texel
  std::vector<uint8_t> flags;      // 1 a texel: FitFlag bits
  std::vector<uint8_t> coverage;   // 1 a texel: copied from the SH image

  size_t size() const { return flags.size(); }
  bool empty() const { return flags.empty(); }
  AhdFit texel(size_t i) const {
    AhdFit f;
    for (int c = 0; c < 3; ++c) {
      f.iz[c] = iz[i * 3 + c];
      f.d[c] = d[i * 3 + c];
      f.ratio[c] = one_ratio ? ratio[i] : ratio[i * 3 + c];
    }
    f.flags = flags[i];
    return f;
  }
  // Stores f as texel i. With one_ratio, f's three ratios must be the same bits (the luminance
  // form's are); otherwise throws ahd::Error rather than drop two of them.
  void set_texel(size_t i, const AhdFit& f);
};

// A w×h AhdImage of zero texels (coverage left empty: the caller copies it), its planes advised
// for huge pages. one_ratio: see AhdImage.
AhdImage make_ahd_image(int width, int height, bool one_ratio);

// How often each rule of the fit fired, over covered texels.
struct FitStats {
  size_t texels = 0;
  size_t covered = 0;
  size_t no_direction = 0;
  size_t dir_clamped = 0;
  size_t negative_iz = 0;
  size_t black = 0;
  size_t guard_reverted = 0;  // refined: texels the pair guard put back to the linear fit (direction_guard.h)
};

// The fit of texel i of an L0 image (plain lightmaps: sh.coeffs == 1), bit for bit fit_image's:
// every texel's fit is the pure ambient lobe (fit_texel_constant: d = z, ratio = 1). Inline: the
// per-texel loops of plain lightmaps (their fit's counts: 4 M texels at 2048²) call it.
inline AhdFit fit_ambient_texel(const ShImage& sh, size_t i, const FitOptions& opt) {
  if (!sh.normals.empty()) {  // rotated zeros may be −0 and decide the sign of a zero I_z: the general route
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    return fit_texel_constant(p, opt);
  }
  // E(z) = e0 + e_z + q_zz with e_z = q_zz = +0 (which also turns −0 into +0).
  const float* t = sh.texel(i);
  const double ez[3] = {l0_irradiance(t[0]) + 0.0, l0_irradiance(t[1]) + 0.0, l0_irradiance(t[2]) + 0.0};
  return fit_constant_irradiance(ez, opt);
}

// One mip level after the fit stage: the SH it was fitted from and the fitted (dilated) AHD.
// The quantiser needs both: the closed loop refits the ratio against the SH.
// An ambient-only level (an L0 image's: mips.h fit_ambient_level) stores no fit: a covered
// texel's is computed from its SH when asked (fit_ambient_texel), and an uncovered texel's SH slot
// (used by nothing else: filtering and measures read covered texels only) holds its dilated I_z.
struct FittedLevel {
  ShImage sh;
  AhdImage ahd;  // the fitted texels; empty in an ambient-only level
};

// Texel i's I_z in an ambient-only level: fit_ambient_texel(sh, i, …).iz for covered texels (the
// cheap form where there are no normals to rotate by), the dilated value for the others.
inline void ambient_level_iz(const ShImage& sh, size_t i, float iz[3]) {
  const float* t = sh.texel(i);
  if (sh.coverage[i] && sh.normals.empty()) {
    for (int c = 0; c < 3; ++c) iz[c] = l0_texel_iz(t[c]);
  } else if (sh.coverage[i]) {
    const AhdFit f = fit_ambient_texel(sh, i, FitOptions{});  // I_z needs no options
    for (int c = 0; c < 3; ++c) iz[c] = f.iz[c];
  } else {
    for (int c = 0; c < 3; ++c) iz[c] = t[c];
  }
}

// ambient_level_iz of texels [first, first + count) into out (count * 3 floats), the same bits:
// the quantiser's I_z plane of an ambient-only level, in loops the compiler vectorises.
void ambient_level_iz_span(const ShImage& sh, size_t first, size_t count, float* out);

// Texel i's I_z, whichever form the level holds: fitted_texel(l, i).iz without making the texel
// (the quantiser's I_z plane reads every texel of every level).
inline void fitted_iz(const FittedLevel& l, size_t i, float iz[3]) {
  if (l.ahd.empty()) return ambient_level_iz(l.sh, i, iz);
  for (int c = 0; c < 3; ++c) iz[c] = l.ahd.iz[i * 3 + c];
}

// Texel i's fit, whichever form the level holds (ambient-only: d = z, ratio = 1, flags 0).
inline AhdFit fitted_texel(const FittedLevel& l, size_t i) {
  if (!l.ahd.empty()) return l.ahd.texel(i);
  AhdFit f{};
  ambient_level_iz(l.sh, i, f.iz);
  for (int c = 0; c < 3; ++c) f.ratio[c] = 1.0f;
  f.d[2] = 1.0f;
  return f;
}

// Fits every texel (uncovered ones too; their values are replaced by dilation later); a refined
// fit then takes the coherence pass (direction_coherence.h) and the pair guard
// (direction_guard.h), both over the whole image, so the bytes depend on neither `threads` nor
// any banding of later stages.
// skip_uncovered: uncovered texels are not fitted and stay zero (d = 0, flags 0): for a caller that
// dilates next (fit_level), since dilate_ahd's result depends on the covered texels alone and
// neither pass above reads an uncovered texel's fit — the dilated image is the same bytes. It
// saves the fit of the gutters (9 % of the texels of the generated 2048² L2 input, more in real
// atlases).
AhdImage fit_image(const ShImage& sh, const FitOptions& opt, int threads, FitStats* stats = nullptr,
                   bool skip_uncovered = false);

// fit_image's counts for an L0 image, whose fit is never stored (every covered texel counts as
// "no direction"). Throws ahd::Error when sh.coeffs != 1.
FitStats ambient_fit_stats(const ShImage& sh, const FitOptions& opt, int threads);

}  // namespace ahd

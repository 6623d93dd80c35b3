#include "fit/fit_image.h"

#include <cmath>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/parallel.h"
#include "fit/direction_coherence.h"

namespace ahd {

AhdImage fit_image(const ShImage& sh, const FitOptions& opt, int threads, FitStats* stats) {
  AhdImage out;
  out.width = sh.width;
  out.height = sh.height;
  out.coverage = sh.coverage;
  assign_large(out.texels, sh.texels(), AhdFit{});
  parallel_for(sh.texels(), threads, 1024, [&](size_t i) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    out.texels[i] = fit_texel(p, opt);
  });
  if (opt.direction_fit == DirectionFit::Refined && opt.coherence_tolerance > 0)
    smooth_directions(sh, opt, threads, &out);
  if (stats) {
    *stats = FitStats{};
    stats->texels = sh.texels();
    for (size_t i = 0; i < sh.texels(); ++i) {
      if (!sh.coverage[i]) continue;
      const uint8_t f = out.texels[i].flags;
      stats->covered++;
      stats->no_direction += (f & kFitNoDirection) != 0;
      stats->dir_clamped += (f & kFitDirClamped) != 0;
      stats->negative_iz += (f & kFitNegativeIz) != 0;
      stats->black += (f & kFitBlack) != 0;
    }
  }
  return out;
}

AhdFit fit_ambient_texel(const ShImage& sh, size_t i, const FitOptions& opt) {
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

FitStats ambient_fit_stats(const ShImage& sh, const FitOptions& opt, int threads) {
  if (sh.coeffs != 1) throw Error("ambient_fit_stats: needs an L0 image (1 coefficient)");
  // The rules' counts per row, summed in row order after (no shared counters between threads).
  struct RowCounts {
    size_t covered = 0, negative = 0, black = 0;
  };
  std::vector<RowCounts> rows(size_t(sh.height));
  const size_t w = size_t(sh.width);
  const bool local = sh.normals.empty();  // tangent-space SH: E(z) straight from coefficient 0
  parallel_for(size_t(sh.height), threads, 8, [&](size_t y) {
    RowCounts& n = rows[y];
    for (size_t i = y * w; i < (y + 1) * w; ++i) {
      if (!sh.coverage[i]) continue;
      n.covered++;
      if (!local) {
        const AhdFit f = fit_ambient_texel(sh, i, opt);
        n.negative += (f.flags & kFitNegativeIz) != 0;
        n.black += (f.flags & kFitBlack) != 0;
        continue;
      }
      // fit_constant_irradiance's two counted flags without the texel (4 M texels at 2048²).
      const float* t = sh.texel(i);
      double iz[3];
      bool negative = false;
      for (int c = 0; c < 3; ++c) {
        const double ez = l0_irradiance(t[c]) + 0.0;
        iz[c] = std::isfinite(ez) ? ez : 0.0;
        if (iz[c] < 0.0) iz[c] = 0.0, negative = true;
      }
      const double lum_iz = opt.luma[0] * iz[0] + opt.luma[1] * iz[1] + opt.luma[2] * iz[2];
      n.negative += negative;
      n.black += !(lum_iz > 0.0);
    }
  });
  FitStats stats;
  stats.texels = sh.texels();
  for (const RowCounts& n : rows) {
    stats.covered += n.covered;
    stats.negative_iz += n.negative;
    stats.black += n.black;
  }
  stats.no_direction = stats.covered;
  return stats;
}

}  // namespace ahd

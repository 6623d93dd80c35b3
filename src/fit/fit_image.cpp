#include "fit/fit_image.h"

#include "core/parallel.h"
#include "fit/direction_coherence.h"

namespace ahd {

AhdImage fit_image(const ShImage& sh, const FitOptions& opt, int threads, FitStats* stats) {
  AhdImage out;
  out.width = sh.width;
  out.height = sh.height;
  out.coverage = sh.coverage;
  out.texels.resize(sh.texels());
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

}  // namespace ahd

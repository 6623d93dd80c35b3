#include "fit/direction_coherence.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "fit/ahd_decode.h"
#include "fit/direction_refine.h"
#include "fit/refine_objective.h"

namespace ahd {

void smooth_directions(const ShImage& sh, const FitOptions& opt, int threads, AhdImage* fit) {
  // The first pass's directions and flags, read-only: all the pass reads of it (the colours and
  // I_z are only written), so not a copy of the whole image.
  const std::vector<float> first_d = fit->d;
  const std::vector<uint8_t> first_flags = fit->flags;
  const int w = fit->width, h = fit->height;
  parallel_for(first_flags.size(), threads, 1024, [&](size_t i) {
    const uint8_t flags = first_flags[i];
    if (!sh.coverage[i] || (flags & (kFitNoDirection | kFitNonFinite))) return;
    const int x = int(i % size_t(w)), y = int(i / size_t(w));
    double ds[3] = {0, 0, 0};
    int count = 0;
    for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy)
      for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx) {
        const size_t j = size_t(yy) * w + xx;
        if (!sh.coverage[j] || (first_flags[j] & (kFitNoDirection | kFitNonFinite))) continue;
        for (int k = 0; k < 3; ++k) ds[k] += first_d[j * 3 + k];
        ++count;
      }
    const double len = std::sqrt(ds[0] * ds[0] + ds[1] * ds[1] + ds[2] * ds[2]);
    if (count < 2 || !(len > 1e-6 * count)) return;
    for (double& v : ds) v /= len;
    tilt_above_horizon(ds, opt.dz_min);
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    double iz[3];
    for (int c = 0; c < 3; ++c) iz[c] = std::max(0.0, p[c].e0 + p[c].e[2] + p[c].q[2][2]);  // as fit_texel
    double db[3] = {first_d[i * 3], first_d[i * 3 + 1], first_d[i * 3 + 2]}, dl[3];
    optimal_direction(p, opt, dl);
    tilt_above_horizon(dl, opt.dz_min);
    const RefineObjective f(p, iz, opt.ratio_form);
    // The mean, the texel's own d and the linear d in one batch (their latencies overlap; the same
    // bytes as three value() calls; the linear d's value is needed by almost every texel that
    // gets this far), keeping the mean's moments for its colours.
    const double* three[3] = {ds, db, dl};
    double fv[3];
    LuneMoments ms[3];
    f.values(three, 3, fv, ms);
    const double fs = fv[0], fb = fv[1], fl = fv[2];
    if (!(fs <= fb)) {
      // Worse than the texel's own: within the tolerance? (Σ_c ∫ E_c² makes f the error itself;
      // only computed here.)
      double e2 = 0;
      for (int c = 0; c < 3; ++c) e2 += hemisphere_square_integral(p[c]);
      if (!(fs - fb <= opt.coherence_tolerance * std::max(0.0, fb + e2))) return;
    }
    if (!(fs <= fl)) return;  // never worse than the linear d
    AhdFit s = fit_colours(p, ds, iz, opt, &ms[0]);  // the same bytes as recomputing the moments
    s.flags |= flags;
    fit->set_texel(i, s);
  });
}

}  // namespace ahd

#include "fit/fit_image.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/parallel.h"
#include "fit/direction_coherence.h"
#include "fit/direction_filter.h"
#include "fit/direction_guard.h"

namespace ahd {

void AhdImage::set_texel(size_t i, const AhdFit& f) {
  for (int c = 0; c < 3; ++c) {
    iz[i * 3 + c] = f.iz[c];
    d[i * 3 + c] = f.d[c];
  }
  if (one_ratio) {
    if (std::memcmp(&f.ratio[0], &f.ratio[1], sizeof(float)) != 0 || std::memcmp(&f.ratio[0], &f.ratio[2], sizeof(float)) != 0)
      throw Error("AhdImage: a texel of the one-ratio (luminance) form has three different ratios");
    ratio[i] = f.ratio[0];
  } else {
    for (int c = 0; c < 3; ++c) ratio[i * 3 + c] = f.ratio[c];
  }
  flags[i] = f.flags;
}

AhdImage make_ahd_image(int width, int height, bool one_ratio) {
  AhdImage a;
  a.width = width;
  a.height = height;
  a.one_ratio = one_ratio;
  const size_t n = size_t(width) * size_t(height);
  assign_large(a.iz, n * 3, 0.0f);
  assign_large(a.d, n * 3, 0.0f);
  assign_large(a.ratio, one_ratio ? n : n * 3, 0.0f);
  assign_large(a.flags, n, uint8_t(0));
  return a;
}

namespace {

// A texel of the windowed refined fit: the direction `win` chose on the window's mean SH, the
// colours solved on the texel's own SH at that d with the texel's own I_z (exact), its own rules
// for I_z. `own` is the texel's linear fit's direction stage (fit_directions); a texel with no
// direction in either stays its linear fit (own_p's, with `linear` options).
AhdFit windowed_texel(const IrradiancePoly own_p[3], const FitDirection& win, const FitDirection& own,
                      const FitOptions& opt, const FitOptions& linear) {
  if ((win.flags & kFitNoDirection) && (own.flags & kFitNoDirection)) return fit_texel(own_p, linear);
  const double d[3] = {win.d[0], win.d[1], win.d[2]};
  const double iz[3] = {own.iz[0], own.iz[1], own.iz[2]};
  AhdFit f = fit_colours(own_p, d, iz, opt);
  f.flags |= (own.flags & (kFitNegativeIz | kFitNonFinite)) | (win.flags & (kFitNoDirection | kFitDirClamped));
  return f;
}

}  // namespace

AhdImage fit_image(const ShImage& sh, const FitOptions& opt, int threads, FitStats* stats, bool skip_uncovered) {
  AhdImage out = make_ahd_image(sh.width, sh.height, opt.ratio_form == RatioForm::Luminance);
  out.coverage = sh.coverage;
  const bool refined = opt.direction_fit == DirectionFit::Refined;
  // A single row or column is not guarded: the random-lighting sets are independent texels laid out
  // n×1, and reverting a texel because of an unrelated one beside it would only lose accuracy.
  const bool guard = refined && opt.pair_guard_deg > 0 && sh.width > 1 && sh.height > 1;
  // The pair guard compares against the linear d, which the fit computes on the way (its first
  // start); the linear colours are refitted only where the guard reverts.
  std::vector<float> linear_d(guard ? sh.texels() * 3 : 0);
  const bool windowed = refined && opt.direction_window > 0 && sh.width > 1 && sh.height > 1;
  std::vector<float> own_linear_d(guard && windowed ? sh.texels() * 3 : 0);  // the windowed guard's second field
  // The coherence pass's comparison with the linear d: that d's objective, which the first pass
  // evaluates as its first start, kept as a float (4 bytes a texel) for the pass to decide on
  // (direction_coherence.h).
  const bool smooth = refined && !windowed && opt.coherence_tolerance > 0;
  std::vector<float> linear_value;
  if (smooth) assign_large(linear_value, sh.texels(), std::numeric_limits<float>::quiet_NaN());
  // Texels in groups of kGroup: fit_texels runs a group's refinements in lockstep (the same bytes
  // as one at a time, so the grouping and the threads' chunks do not change the output). With
  // skip_uncovered a group gathers the next covered texels of its block.
  constexpr size_t kGroup = 4, kBlock = 256;
  const size_t texels = sh.texels(), blocks = (texels + kBlock - 1) / kBlock;
  FitOptions linear = opt;
  linear.direction_fit = DirectionFit::Linear;
  parallel_for(blocks, threads, 4, [&](size_t b) {
    const size_t end = std::min(texels, (b + 1) * kBlock);
    for (size_t next = b * kBlock; next < end;) {
      size_t at[kGroup];
      int n = 0;
      for (; next < end && n < int(kGroup); ++next)
        if (!skip_uncovered || sh.coverage[next]) at[n++] = next;
      IrradiancePoly p[3 * kGroup];
      for (int k = 0; k < n; ++k) local_polys(sh, at[k], &p[3 * k]);
      float lin[3 * kGroup], own_lin[3 * kGroup];
      if (!windowed) {
        AhdFit f[kGroup];
        double lv[kGroup];
        fit_texels(p, n, opt, f, guard ? lin : nullptr, smooth ? lv : nullptr);
        for (int k = 0; k < n; ++k) out.set_texel(at[k], f[k]);
        if (smooth)
          for (int k = 0; k < n; ++k) linear_value[at[k]] = float(lv[k]);
      } else {
        // Only the directions of the window's refined fit and of the texel's own linear fit are kept
        // (windowed_texel): their colours are not solved.
        IrradiancePoly w[3 * kGroup];
        for (int k = 0; k < n; ++k) window_local_polys(sh, at[k], opt.direction_window, &w[3 * k]);
        FitDirection fw[kGroup], fo[kGroup];
        fit_directions(w, n, opt, fw, guard ? lin : nullptr);  // the guard's field: the window's linear d
        fit_directions(p, n, linear, fo, guard ? own_lin : nullptr);
        for (int k = 0; k < n; ++k) out.set_texel(at[k], windowed_texel(&p[3 * k], fw[k], fo[k], opt, linear));
        if (guard)
          for (int k = 0; k < n; ++k) std::copy_n(own_lin + 3 * k, 3, &own_linear_d[at[k] * 3]);
      }
      if (guard)
        for (int k = 0; k < n; ++k) std::copy_n(lin + 3 * k, 3, &linear_d[at[k] * 3]);
    }
  });
  if (smooth) {
    smooth_directions(sh, opt, threads, &out, linear_value.data());
    std::vector<float>().swap(linear_value);
  }
  size_t reverted = 0;
  // Windowed: a reverted texel takes the window's linear d (the field linear_d holds) with its own
  // colours; a pair may turn as far as either linear field does (the window's, or the texels' own:
  // on a noisy bake that one turns fast, and reverting to follow the window's alone would undo the
  // window's gain).
  const auto windowed_linear = [&](size_t i) {
    IrradiancePoly p[3], w[3];
    local_polys(sh, i, p);
    window_local_polys(sh, i, opt.direction_window, w);
    FitDirection fw, fo;
    fit_directions(w, 1, linear, &fw, nullptr);
    fit_directions(p, 1, linear, &fo, nullptr);
    return windowed_texel(p, fw, fo, opt, linear);
  };
  if (guard) reverted = guard_direction_pairs(sh, opt, linear_d, threads, &out, windowed ? std::function<AhdFit(size_t)>(windowed_linear) : nullptr,
                                              windowed ? &own_linear_d : nullptr);
  if (stats) {
    *stats = FitStats{};
    stats->texels = sh.texels();
    stats->guard_reverted = reverted;
    for (size_t i = 0; i < sh.texels(); ++i) {
      if (!sh.coverage[i]) continue;
      const uint8_t f = out.flags[i];
      stats->covered++;
      stats->no_direction += (f & kFitNoDirection) != 0;
      stats->dir_clamped += (f & kFitDirClamped) != 0;
      stats->negative_iz += (f & kFitNegativeIz) != 0;
      stats->black += (f & kFitBlack) != 0;
    }
  }
  return out;
}

void ambient_level_iz_span(const ShImage& sh, size_t first, size_t count, float* out) {
  if (!sh.normals.empty()) {
    for (size_t j = 0; j < count; ++j) ambient_level_iz(sh, first + j, &out[j * 3]);
    return;
  }
  const float* t = sh.texel(first);
  const uint8_t* cov = &sh.coverage[first];
  for (size_t j = 0; j < count; ++j)
    for (int c = 0; c < 3; ++c) out[j * 3 + c] = cov[j] ? l0_texel_iz(t[j * 3 + c]) : t[j * 3 + c];
}

FitStats ambient_fit_stats(const ShImage& sh, const FitOptions& opt, int threads) {
  if (sh.coeffs != 1) throw Error("ambient_fit_stats: needs an L0 image (1 coefficient)");
  // The rules' counts per row, summed in row order after (no shared counters between threads).
  struct RowCounts {
    size_t covered = 0, negative = 0, black = 0;
  };
  std::vector<RowCounts> rows(size_t(sh.height));
  const size_t w = size_t(sh.width);
  parallel_for(size_t(sh.height), threads, 8, [&](size_t y) {
    RowCounts& n = rows[y];
    for (size_t i = y * w; i < (y + 1) * w; ++i) {
      if (!sh.coverage[i]) continue;
      const AhdFit f = fit_ambient_texel(sh, i, opt);
      n.covered++;
      n.negative += (f.flags & kFitNegativeIz) != 0;
      n.black += (f.flags & kFitBlack) != 0;
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

// The windowed refined fit's cheaper forms (docs/fit.md "The windowed fit's cost") give the bytes of
// the plain forms: the direction stage alone, the unrolled window sums, and skipping the texels
// dilation replaces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "core/option_enums.h"
#include "fit_bits.h"
#include "fit/direction_coherence.h"
#include "fit/direction_filter.h"
#include "fit/fit_image.h"
#include "lab/hard_cases.h"
#include "mips/dilate.h"
#include "sample/analytic_baker.h"

namespace ahd {
namespace {

ShImage window_scene(int coeffs, bool normals, int width = 48, int height = 48) {
  BakerOptions bo;
  bo.width = width;
  bo.height = height;
  bo.coeffs = coeffs;
  ShImage sh = bake_analytic_scene(bo);
  // Multiplicative noise (a Monte-Carlo bake's), so that neighbours differ and the window matters.
  uint32_t state = 777;
  for (float& v : sh.data) {
    state = state * 1664525u + 1013904223u;
    v *= 1.0f + 0.3f * (float(state >> 8) / float(1u << 24) - 0.5f);
  }
  if (normals) {
    sh.normals.assign(sh.texels() * 3, 0.0f);
    for (size_t i = 0; i < sh.texels(); ++i) {
      const float t = 0.01f * float(i % 97);
      sh.normals[i * 3] = t, sh.normals[i * 3 + 1] = -0.5f * t, sh.normals[i * 3 + 2] = 1.0f;
      const float len = std::sqrt(1.0f + 1.25f * t * t);
      for (int k = 0; k < 3; ++k) sh.normals[i * 3 + k] /= len;
    }
  }
  return sh;
}

bool same_poly_bits(const IrradiancePoly& a, const IrradiancePoly& b) {
  return std::memcmp(&a.e0, &b.e0, sizeof a.e0) == 0 && std::memcmp(a.e, b.e, sizeof a.e) == 0 &&
         std::memcmp(a.q, b.q, sizeof a.q) == 0;
}

// window_local_polys as first written (the generic loop over sh.coeffs × 3): the reference.
void reference_window_polys(const ShImage& sh, size_t i, int radius, IrradiancePoly out[3]) {
  const int n = sh.coeffs * 3;
  double sum[kShCoeffsL2 * 3] = {};
  int count = 0;
  const int x = int(i % size_t(sh.width)), y = int(i / size_t(sh.width));
  for (int yy = y - radius; yy <= y + radius; ++yy) {
    if (yy < 0 || yy >= sh.height) continue;
    for (int xx = x - radius; xx <= x + radius; ++xx) {
      if (xx < 0 || xx >= sh.width) continue;
      const size_t j = size_t(yy) * size_t(sh.width) + size_t(xx);
      if (j != i && !sh.coverage[j]) continue;
      const float* t = sh.texel(j);
      for (int k = 0; k < n; ++k) sum[k] += t[k];
      ++count;
    }
  }
  float mean[kShCoeffsL2 * 3] = {};  // only the first n are read (zeroed: GCC 12 cannot see it)
  for (int k = 0; k < n; ++k) mean[k] = float(sum[k] / count);
  for (int c = 0; c < 3; ++c) out[c] = irradiance_poly(mean + c, sh.coeffs, 3);
  if (sh.normals.empty()) return;
  const float* nf = sh.normals.data() + i * 3;
  const double nd[3] = {nf[0], nf[1], nf[2]};
  double R[3][3];
  frame_from_normal(nd, R);
  for (int c = 0; c < 3; ++c) out[c] = rotate_poly(out[c], R);
}

TEST(FitWindowCost, UnrolledWindowSumsGiveTheGenericLoopsBytes) {
  // L2 and L1 take the unrolled sums, L0 the generic loop; radii 1 and 2; with and without normals;
  // every texel, edges and gutters included.
  size_t checked = 0;
  for (int coeffs : {9, 4, 1})
    for (bool normals : {false, true})
      for (int radius : {1, 2}) {
        const ShImage sh = window_scene(coeffs, normals);
        for (size_t i = 0; i < sh.texels(); ++i) {
          IrradiancePoly a[3], b[3];
          window_local_polys(sh, i, radius, a);
          reference_window_polys(sh, i, radius, b);
          for (int c = 0; c < 3; ++c) ASSERT_TRUE(same_poly_bits(a[c], b[c])) << coeffs << " " << i << " " << c;
          ++checked;
        }
      }
  EXPECT_EQ(checked, size_t(3 * 2 * 2 * 48 * 48));
}

TEST(FitWindowCost, DirectionStageAloneGivesTheFitsDirectionIzAndFlags) {
  // fit_directions against fit_texels, 1–4 texels at once, on the noisy scene and the hard cases
  // (non-finite, negative I_z, no direction, grazing), both fits and both ratio forms.
  std::vector<IrradiancePoly> polys;
  for (const ShImage& sh : {window_scene(9, false), window_scene(9, true), window_scene(4, false)})
    for (size_t i = 0; i < sh.texels(); i += 3) {
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      polys.insert(polys.end(), p, p + 3);
    }
  for (const HardCase& hc : hard_cases())
    for (size_t i = 0; i < hc.sh.texels(); ++i) {
      IrradiancePoly p[3];
      local_polys(hc.sh, i, p);
      polys.insert(polys.end(), p, p + 3);
    }
  const size_t texels = polys.size() / 3;
  size_t constant = 0, no_direction = 0;
  for (const auto& [fit, fit_name, fit_cpp] : kDirectionFits)  // every strategy
    for (RatioForm form : {RatioForm::Luminance, RatioForm::Rgb})
      for (int n = 1; n <= 4; ++n)
        for (size_t i0 = 0; i0 + size_t(n) <= texels; i0 += size_t(n)) {
          FitOptions opt;
          opt.direction_fit = fit;
          opt.ratio_form = form;
          AhdFit f[4];
          FitDirection d[4];
          float lf[12], ld[12];
          fit_texels(&polys[i0 * 3], n, opt, f, lf);
          fit_directions(&polys[i0 * 3], n, opt, d, ld);
          ASSERT_EQ(std::memcmp(lf, ld, sizeof(float) * 3 * size_t(n)), 0) << "linear d, texel " << i0;
          for (int k = 0; k < n; ++k) {
            ASSERT_EQ(std::memcmp(f[k].d, d[k].d, sizeof f[k].d), 0) << "texel " << i0 + k;
            ASSERT_EQ(std::memcmp(f[k].iz, d[k].iz, sizeof f[k].iz), 0) << "texel " << i0 + k;
            const uint8_t want = d[k].constant ? f[k].flags : uint8_t(f[k].flags & ~kFitBlack);
            ASSERT_EQ(want, d[k].flags) << "texel " << i0 + k;
            constant += d[k].constant;
            no_direction += (d[k].flags & kFitNoDirection) != 0;
          }
        }
  EXPECT_GT(constant, 0u);  // the hard cases reach both early rules
  EXPECT_GT(no_direction, constant);
}

TEST(FitWindowCost, SkippingUncoveredTexelsGivesTheSameDilatedLevel) {
  // fit_level's form: the uncovered texels are not fitted, and after dilate_ahd every byte (and
  // every count) is what fitting them first gives — for the windowed refined default, the
  // per-texel refined fit (coherence pass) and the linear fit, on 1 and 3 threads.
  const ShImage sh = window_scene(9, false);
  size_t uncovered = 0;
  for (uint8_t c : sh.coverage) uncovered += c == 0;
  ASSERT_GT(uncovered, sh.texels() / 20) << "the scene should have gutters";
  for (int variant = 0; variant < 4; ++variant) {
    FitOptions opt;
    opt.direction_fit = variant == 3 ? DirectionFit::Linear : DirectionFit::Refined;
    if (variant == 1) opt.direction_window = 0;
    if (variant == 2) opt.ratio_form = RatioForm::Rgb;
    FitStats sa, sb;
    AhdImage a = fit_image(sh, opt, 1, &sa);
    AhdImage b = fit_image(sh, opt, 3, &sb, /*skip_uncovered=*/true);
    EXPECT_EQ(sa.covered, sb.covered);
    EXPECT_EQ(sa.guard_reverted, sb.guard_reverted) << "variant " << variant;
    EXPECT_EQ(sa.dir_clamped, sb.dir_clamped);
    EXPECT_EQ(sa.no_direction, sb.no_direction);
    dilate_ahd(a, opt.dz_min, 1);
    dilate_ahd(b, opt.dz_min, 3);
    for (size_t i = 0; i < sh.texels(); ++i)
      ASSERT_TRUE(same_fit_bits(a.texel(i), b.texel(i))) << "variant " << variant << ", texel " << i;
  }
}

TEST(FitWindowCost, CoherencePassFromTheFirstPassValuesGivesTheSameBytes) {
  // fit_image hands the coherence pass the first pass's objective at each linear d (as floats):
  // its fit is, byte for byte, the first pass followed by the pass that computes them all again —
  // L1 and L2, both ratio forms, on 1 and 2 threads, 4 bands of rows (the pass works in place).
  for (int coeffs : {4, 9})
    for (RatioForm form : {RatioForm::Luminance, RatioForm::Rgb}) {
      const ShImage sh = window_scene(coeffs, false, 160, 100);
      FitOptions opt;
      opt.direction_fit = DirectionFit::Refined;
      opt.ratio_form = form;
      ASSERT_GT(opt.coherence_tolerance, 0.0);
      ASSERT_EQ(opt.direction_window, 0);
      FitOptions first_only = opt;
      first_only.coherence_tolerance = 0;
      AhdImage recomputed = fit_image(sh, first_only, 1);
      const AhdImage first = recomputed;
      smooth_directions(sh, opt, 1, &recomputed);  // no values at hand: every one computed
      size_t moved = 0;
      for (size_t i = 0; i < sh.texels(); ++i) moved += !same_fit_bits(first.texel(i), recomputed.texel(i));
      EXPECT_GT(moved, sh.texels() / 20) << "the pass should move directions (coeffs " << coeffs << ")";
      for (int threads : {1, 2}) {
        const AhdImage reused = fit_image(sh, opt, threads);
        for (size_t i = 0; i < sh.texels(); ++i)
          ASSERT_TRUE(same_fit_bits(recomputed.texel(i), reused.texel(i)))
              << "coeffs " << coeffs << ", texel " << i << ", " << threads << " thread(s)";
      }
    }
}

}  // namespace
}  // namespace ahd

// The direction choice against path-traced lighting (issue 27): the scenes in tests/data/truth
// (scripts/truth/bake_truth.py, Blender Cycles) made into baker-like SH, converted with the
// defaults, decoded at the held-out normals and compared with what Cycles computed there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "api/options.h"
#include "fit/ahd_decode.h"
#include "lab/fit_quality.h"
#include "lab/truth_baker_formats.h"
#include "lab/truth_reference.h"
#include "lab/truth_file.h"
#include "pipeline/convert.h"
#include "pipeline/plane_decode.h"
#include "sh/sh_image.h"
#include "test_data.h"

namespace ahd {
namespace {

// The corpus (scripts/truth/bake_corpus.sh): the fit's choices were tuned on "area" and "sun"; the
// others are held out (docs/accuracy-real-lighting.md "The corpus"). The two 256² scenes are
// measured by `ahdpack report truth` only (a minute or two each, too long for the suite).
const char* const kScenes[] = {"area", "sun", "cornell_area", "cornell_sun", "lamps", "emissive", "cornell_tight"};
// Bakes with ≥ 128 samples a texel: their SH reproduces the training normals within 15 %; at 16
// (emissive) the Monte-Carlo noise alone is more than L2 holds (measured 0.18).
const char* const kCleanScenes[] = {"area", "sun", "cornell_area", "cornell_sun", "lamps", "cornell_tight"};

std::string scene_dir(const char* name) { return ahd_test::test_data(std::string("truth/") + name).string(); }

TEST(Truth, TheBakerSHReproducesTheTrainingNormals) {
  // The SH is what a baker would store: its irradiance at the normals it was made from is close
  // to Cycles' (not exact: L2 cannot hold every detail, and radiance is kept non-negative).
  for (const char* name : kCleanScenes) {
    const TruthSet t = load_truth_set(scene_dir(name));
    const ShImage sh = baker_sh(t, 9, 0);
    double num = 0, den = 0;
    for (size_t i = 0; i < t.texels(); ++i) {
      if (!t.coverage[i]) continue;
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      for (size_t k = 0; k < t.normals.size(); ++k) {
        if (t.held_out[k]) continue;
        for (int c = 0; c < 3; ++c)
          num += std::fabs(eval_irradiance(p[c], t.normals[k].data()) - t.e[k][i * 3 + c]), den += t.e[k][i * 3 + c];
      }
    }
    EXPECT_LT(num / den, 0.15) << name;
    EXPECT_GT(num / den, 0.0) << name;
  }
}

TEST(Truth, DefaultConversionIsWithinFivePercentOfTheSearchedDirection) {
  for (const char* name : kScenes) {
    const TruthSet t = load_truth_set(scene_dir(name));
    const ShImage sh = baker_sh(t, 9, 0);
    ShImage l1 = make_sh_image(t.width, t.height, 4);
    l1.coverage = sh.coverage;
    for (size_t i = 0; i < t.texels(); ++i)
      for (int k = 0; k < 12; ++k) l1.texel(i)[k] = sh.texel(i)[k];
    const double l1_error = truth_errors(t, [&l1](size_t i, const double n[3], double out[3]) {
                              IrradiancePoly q[3];
                              local_polys(l1, i, q);
                              for (int c = 0; c < 3; ++c) out[c] = eval_irradiance(q[c], n);
                            }).held_out;
    ConversionOptions co;
    co.profile = "pc-bc";
    const ResolvedOptions defaults_all = resolve_options(co, "truth");
    const FitOptions defaults = defaults_all.convert.fit;
    const AhdImage searched = searched_direction_fit(sh, defaults, 300);
    const double reference = truth_errors(t, ahd_image_eval(searched, defaults.dz_min)).held_out;

    PipelineOptions opt = defaults_all.convert;
    opt.max_levels = 1;
    opt.direction = DirectionPlanes::Keep;
    const Profile& prof = defaults_all.profile;
    const PipelineResult r = run_conversion(sh, prof, opt);
    const DecodedPlanes p = decode_planes(r.planes, prof.ratio_rgb, 0);
    const double ours = truth_errors(t, [&p](size_t i, const double n[3], double out[3]) {
                          decode_irradiance(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], n, FitOptions{}.dz_min, out);
                        }).held_out;
    EXPECT_LE(ours, 1.05 * reference) << name << ": default pc-bc " << ours << ", searched d " << reference;
    EXPECT_LT(ours, l1_error) << name << ": default pc-bc " << ours << ", float L1 SH " << l1_error;

    // The fitted planes before quantisation: I_z exact, and halfway between texels (the planes
    // filtered, where neighbouring directions may differ) within 1 % of the linear fit's (measured:
    // lower on every scene but the 16-sample emissive one, 0.2270 against 0.2262).
    const AhdImage fit = fit_image(sh, defaults, 0);
    FitOptions linear = defaults;
    linear.direction_fit = DirectionFit::Linear;
    const AhdImage lin = fit_image(sh, linear, 0);
    EXPECT_LE(truth_between_error(t, ahd_image_pair_eval(fit, defaults.dz_min)),
              1.01 * truth_between_error(t, ahd_image_pair_eval(lin, defaults.dz_min))) << name;
    double worst = 0;
    for (size_t i = 0; i < t.texels(); ++i) {
      if (!sh.coverage[i]) continue;
      IrradiancePoly q[3];
      local_polys(sh, i, q);
      const double z[3] = {0, 0, 1};
      for (int c = 0; c < 3; ++c) {
        const double ez = std::max(0.0, eval_irradiance(q[c], z));
        worst = std::max(worst, std::fabs(double(fit.iz[i * 3 + c]) - ez) / std::max(ez, 1e-3));
      }
    }
    EXPECT_LT(worst, 1e-6) << name;
  }
}

}  // namespace
}  // namespace ahd

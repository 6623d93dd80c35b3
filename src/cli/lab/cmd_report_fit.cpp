// ahdpack report fit: the paper's linear direction against the refined one (issue 18), both ratio
// forms, on random lighting and the analytic scene: hemisphere error of the fitted and of the
// quantised planes against the unconstrained LS fit at the linear d (exact integrals, and the
// issue's own sampled measure: 400 directions, mean of per-texel ratios and ratio of means), the angle
// between neighbours' d, the error between texel centres under bilinear filtering, and fit speed.
#include <time.h>

#include <cstdio>
#include <string>
#include <vector>

#include "files/profile_file.h"
#include "cli/commands.h"
#include "core/option_enums.h"
#include "fit/direction_refine.h"
#include "lab/fit_quality.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"

namespace ahd::cli {

namespace {

double thread_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// The planes a conversion wrote (level 0, as the reference decoder reads them) as an AhdImage.
AhdImage quantised_planes(const ShImage& sh, const FitOptions& fit) {
  const bool rgb = fit.ratio_form == RatioForm::Rgb;
  PipelineOptions opt;
  opt.fit = fit;
  opt.measure = Measure::Off;
  opt.max_levels = 1;
  opt.direction = DirectionPlanes::Keep;
  const PipelineResult r = run_conversion(sh, load_profile(rgb ? "uncompressed-rgb" : "uncompressed"), opt);
  const DecodedPlanes p = decode_planes(r.planes, rgb, 0);
  AhdImage a = make_ahd_image(sh.width, sh.height, false);  // the decoded ratios, three a texel
  a.coverage = sh.coverage;
  for (size_t i = 0; i < sh.texels(); ++i) {
    AhdFit f{};
    for (int c = 0; c < 3; ++c) {
      f.iz[c] = p.iz[i * 3 + c];
      f.d[c] = p.d[i * 3 + c];
      f.ratio[c] = p.ratio[i * 3 + c];
    }
    a.set_texel(i, f);
  }
  return a;
}

// The sets the report measures: issue 18's calibrated ones (its "today" column) and the harder
// ones of the first round (independent light colours, the canonical analytic scene).
struct FitSets {
  int size = 128, random_texels = 20000;
  double saturation = kCalibratedSaturation;           // the calibrated random set's light colours
  double ambient = kCalibratedAmbient;
  double point_scale = kSmoothPointScale, sky_scale = kSmoothSkyScale;  // the smooth scene
  double ceiling_scale = kSmoothCeilingScale, bounce_scale = kSmoothBounceScale;
  int smooth_coeffs = kSmoothCoeffs;
  bool hard = true;          // also the harder sets
  bool refined = true;       // also the refined fit (off: a quick calibration run)
  double coherence = FitOptions{}.coherence_tolerance;
  double guard = FitOptions{}.pair_guard_deg;
};

void report_fit(const FitSets& fs) {
  BakerOptions canonical;
  canonical.width = canonical.height = fs.size;
  BakerOptions smooth = canonical;
  smooth.point_scale = fs.point_scale, smooth.sky_scale = fs.sky_scale;
  smooth.ceiling_scale = fs.ceiling_scale, smooth.bounce_scale = fs.bounce_scale;
  smooth.coeffs = fs.smooth_coeffs;
  std::vector<ShImage> sets;
  std::vector<std::string> names;
  char buf[96];
  std::snprintf(buf, sizeof buf, "random lighting, saturation %.2f, ambient %.2f", fs.saturation, fs.ambient);
  sets.push_back(random_lighting_set(fs.random_texels, 7, fs.saturation, fs.ambient)), names.push_back(buf);
  std::snprintf(buf, sizeof buf, "smooth scene %d² %s (point ×%.2g, sky ×%.2g, ceiling ×%.2g, bounce ×%.2g)",
                fs.size, fs.smooth_coeffs == 4 ? "L1" : "L2", fs.point_scale, fs.sky_scale, fs.ceiling_scale,
                fs.bounce_scale);
  sets.push_back(bake_analytic_scene(smooth)), names.push_back(buf);
  if (fs.hard) {
    sets.push_back(random_lighting_set(fs.random_texels, 7, 1.0)), names.push_back("random lighting, independent colours");
    std::snprintf(buf, sizeof buf, "analytic scene %d²", fs.size);
    sets.push_back(bake_analytic_scene(canonical)), names.push_back(buf);
  }
  std::printf("| set | ratio | direction fit | fitted / LS | quantised / LS | issue 18: mean of texel ratios "
              "(400 dirs) | issue 18: ratio of means (400 dirs) | neighbour angle p99 (°) | "
              "bilinear sub-texel rel RMSE | pair guard: reverted | fit ns/texel (thread CPU) |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (size_t s = 0; s < sets.size(); ++s)
    for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance})
      for (const auto& [dir, dir_name, dir_cpp] : kDirectionFits) {
        if (dir != DirectionFit::Linear && !fs.refined) continue;  // the paper's fit, the others when asked
        FitOptions opt;
        opt.ratio_form = form;
        opt.direction_fit = dir;
        opt.coherence_tolerance = fs.coherence;
        opt.pair_guard_deg = fs.guard;
        FitStats st;
        const double t0 = thread_seconds();
        const AhdImage fit = fit_image(sets[s], opt, 1, &st);
        const double ns = 1e9 * (thread_seconds() - t0) / double(sets[s].texels());
        const FitQuality qf = fit_quality(sets[s], fit, opt, 0, /*directions=*/400);
        const FitQuality qq = fit_quality(sets[s], quantised_planes(sets[s], opt), opt, 0);
        char angle[32] = "–", filtered[32] = "–";
        if (sets[s].height > 1) {  // the random set is independent texels: no neighbours
          const FilteredError fe = filtered_error(sets[s], fit, opt);
          std::snprintf(angle, sizeof angle, "%.2f", direction_p99_angle_deg(fit));
          std::snprintf(filtered, sizeof filtered, "%.4f", fe.mean_irradiance > 0 ? fe.rms / fe.mean_irradiance : 0.0);
        }
        char reverted[32] = "–";
        if (dir == DirectionFit::Refined && opt.pair_guard_deg > 0 && st.covered && sets[s].height > 1)
          std::snprintf(reverted, sizeof reverted, "%.2f %%", 100.0 * double(st.guard_reverted) / double(st.covered));
        std::printf("| %s | %s | %s | %.3f | %.3f | %.3f | %.3f | %s | %s | %s | %.0f |\n", names[s].c_str(),
                    form == RatioForm::Rgb ? "rgb" : "luminance", dir_name, qf.ratio(), qq.ratio(),
                    qf.sampled_texel_ratio, qf.sampled_ratio, angle, filtered, reverted, ns);
        std::fflush(stdout);
      }
}

}  // namespace

void add_report_fit_command(CLI::App* report) {
  CLI::App* f = report->add_subcommand("fit", "Linear vs refined direction fit: error vs unconstrained LS, coherence, speed");
  auto fs = std::make_shared<FitSets>();
  f->add_option("--size", fs->size, "Analytic scene size")->check(CLI::Range(2, 4096));
  f->add_option("--random", fs->random_texels, "Random-lighting texels")->check(CLI::Range(1, 10000000));
  f->add_option("--saturation", fs->saturation, "Light-colour saturation of the calibrated random set")
      ->check(CLI::Range(0.0, 1.0));
  f->add_option("--point-scale", fs->point_scale, "Smooth scene: point-light intensity scale")->check(CLI::Range(0.0, 100.0));
  f->add_option("--sky-scale", fs->sky_scale, "Smooth scene: sky radiance scale")->check(CLI::Range(0.0, 1000.0));
  f->add_option("--ambient", fs->ambient, "Calibrated random set: ambient relative to a light")->check(CLI::Range(0.0, 100.0));
  f->add_option("--ceiling-scale", fs->ceiling_scale, "Smooth scene: ceiling area light scale")->check(CLI::Range(0.0, 100.0));
  f->add_option("--bounce-scale", fs->bounce_scale, "Smooth scene: coloured bounce light scale")->check(CLI::Range(0.0, 100.0));
  f->add_option("--smooth-coeffs", fs->smooth_coeffs, "Smooth scene: 4 (L1) or 9 (L2)")->check(CLI::IsMember({4, 9}));
  f->add_option("--coherence", fs->coherence, "Refined: coherence tolerance (0 = off)")->check(CLI::Range(0.0, 1.0));
  f->add_option("--guard", fs->guard, "Refined: pair guard angle T in degrees (0 = off)")->check(CLI::Range(0.0, 90.0));
  f->add_flag("!--no-hard", fs->hard, "Only the calibrated sets");
  f->add_flag("!--no-refined", fs->refined, "Only the linear fit (calibration)");
  f->callback([fs]() { report_fit(*fs); });
}

}  // namespace ahd::cli

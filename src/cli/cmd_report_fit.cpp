// ahdpack report fit: the paper's linear direction against the refined one (issue 18), both ratio
// forms, on random lighting and the analytic scene: hemisphere error of the fitted and of the
// quantised planes against the unconstrained LS fit at the linear d (exact integrals, and the
// issue's own sampled measure: 400 directions, mean of per-texel ratios and ratio of means), the angle
// between neighbours' d, the error between texel centres under bilinear filtering, and fit speed.
#include <time.h>

#include <cstdio>

#include "io/profile_file.h"
#include "cli/commands.h"
#include "fit/direction_refine.h"
#include "fit/fit_quality.h"
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
  ConvertOptions opt;
  opt.fit = fit;
  opt.measure = Measure::Off;
  opt.max_levels = 1;
  opt.direction = DirectionPlanes::Keep;
  const ConvertResult r = convert(sh, load_profile(rgb ? "uncompressed-rgb" : "uncompressed"), opt);
  const DecodedPlanes p = decode_planes(r.planes, rgb, 0);
  AhdImage a;
  a.width = sh.width, a.height = sh.height, a.coverage = sh.coverage;
  a.texels.resize(sh.texels());
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      a.texels[i].iz[c] = p.iz[i * 3 + c];
      a.texels[i].d[c] = p.d[i * 3 + c];
      a.texels[i].ratio[c] = p.ratio[i * 3 + c];
    }
  return a;
}

void report_fit(int size, int random_texels) {
  BakerOptions bo;
  bo.width = bo.height = size;
  const ShImage sets[2] = {random_lighting_set(random_texels, 7), bake_analytic_scene(bo)};
  const char* names[2] = {"random lighting", "analytic scene"};
  std::printf("| set | ratio | direction fit | fitted / LS | quantised / LS | issue 18: mean of texel ratios "
              "(400 dirs) | issue 18: ratio of means (400 dirs) | neighbour angle p99 (°) | "
              "bilinear sub-texel rel RMSE | fit ns/texel (thread CPU) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (int s = 0; s < 2; ++s)
    for (RatioForm form : {RatioForm::Rgb, RatioForm::Luminance})
      for (DirectionFit dir : {DirectionFit::Linear, DirectionFit::Refined}) {
        FitOptions opt;
        opt.ratio_form = form;
        opt.direction_fit = dir;
        const double t0 = thread_seconds();
        const AhdImage fit = fit_image(sets[s], opt, 1);
        const double ns = 1e9 * (thread_seconds() - t0) / double(sets[s].texels());
        const FitQuality qf = fit_quality(sets[s], fit, opt, 0, /*directions=*/400);
        const FitQuality qq = fit_quality(sets[s], quantised_planes(sets[s], opt), opt, 0);
        char angle[32] = "–", filtered[32] = "–";
        if (sets[s].height > 1) {  // the random set is independent texels: no neighbours
          const FilteredError fe = filtered_error(sets[s], fit, opt);
          std::snprintf(angle, sizeof angle, "%.2f", direction_p99_angle_deg(fit));
          std::snprintf(filtered, sizeof filtered, "%.4f", fe.mean_irradiance > 0 ? fe.rms / fe.mean_irradiance : 0.0);
        }
        std::printf("| %s | %s | %s | %.3f | %.3f | %.3f | %.3f | %s | %s | %.0f |\n", names[s],
                    form == RatioForm::Rgb ? "rgb" : "luminance", direction_fit_name(dir), qf.ratio(), qq.ratio(),
                    qf.sampled_texel_ratio, qf.sampled_ratio, angle, filtered, ns);
      }
}

}  // namespace

void add_report_fit_command(CLI::App* report) {
  CLI::App* f = report->add_subcommand("fit", "Linear vs refined direction fit: error vs unconstrained LS, coherence, speed");
  auto size = std::make_shared<int>(128);
  auto random = std::make_shared<int>(20000);
  f->add_option("--size", *size, "Analytic scene size")->check(CLI::Range(2, 4096));
  f->add_option("--random", *random, "Random-lighting texels")->check(CLI::Range(1, 10000000));
  f->callback([size, random]() { report_fit(*size, *random); });
}

}  // namespace ahd::cli

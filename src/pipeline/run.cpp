#include "pipeline/run.h"

#include <chrono>

#include "pipeline/pages.h"

namespace ahd {
namespace {

using Clock = std::chrono::steady_clock;

// Package run.result (its planes complete) and total the seconds.
ConversionRun package(ConversionRun run, const Profile& profile, const PipelineOptions& opt, const PackageOptions& pkg,
                      double prior_seconds, Clock::time_point t0) {
  opt.step("write", 0);
  const auto t_pack = Clock::now();
  const double before_pack = prior_seconds + std::chrono::duration<double>(t_pack - t0).count();
  run.output = package_conversion(run.result, profile, opt.fit, pkg, before_pack);
  const double pack = std::chrono::duration<double>(Clock::now() - t_pack).count();
  run.result.timings.push_back({"package", pack});
  run.seconds = before_pack + pack;
  opt.step("write", 1);
  return run;
}

// Quantise the fitted levels and package the result; `run` already holds the earlier stages.
ConversionRun finish(ConversionRun run, const std::vector<FittedLevel>& levels, const Profile& profile,
                     const PipelineOptions& opt, const PackageOptions& pkg, double prior_seconds,
                     Clock::time_point t0) {
  quantise_levels(levels, profile, opt, &run.result);
  return package(std::move(run), profile, opt, pkg, prior_seconds, t0);
}

// Stored I_z = iz_scale × E: the SH is linear in the light, so scaling it scales I_z and both
// colours and keeps d and the ratio.
void scale_sh(ShImage& sh, double iz_scale) {
  if (iz_scale != 1.0)
    for (float& v : sh.data) v = float(double(v) * iz_scale);
}

double sum_seconds(const std::vector<StageCost>& stages) {
  double s = 0;
  for (const StageCost& c : stages) s += c.seconds;
  return s;
}

}  // namespace

ConversionRun run_conversion(ShImage sh, const Profile& profile, const PipelineOptions& opt,
                             const PackageOptions& pkg, std::vector<StageCost> prior,
                             const std::function<void(const std::vector<FittedLevel>&)>& on_fitted) {
  check_profile(profile, opt);
  const auto t0 = Clock::now();
  const double prior_seconds = sum_seconds(prior);
  scale_sh(sh, pkg.iz_scale);
  ConversionRun run;
  if (!on_fitted) {  // level by level: the chain of fitted levels never exists at once
    run.result = run_conversion(std::move(sh), profile, opt);
    run.result.timings.insert(run.result.timings.begin(), prior.begin(), prior.end());
    return package(std::move(run), profile, opt, pkg, prior_seconds, t0);
  }
  run.result.timings = std::move(prior);
  const std::vector<FittedLevel> levels = fit_levels(std::move(sh), opt, &run.result);
  const auto t = Clock::now();
  on_fitted(levels);
  run.result.timings.push_back({"intermediate", std::chrono::duration<double>(Clock::now() - t).count()});
  return finish(std::move(run), levels, profile, opt, pkg, prior_seconds, t0);
}

ConversionRun run_pages(std::vector<ShImage> pages, const Profile& profile, const PipelineOptions& opt,
                        const PackageOptions& pkg, std::vector<StageCost> prior) {
  check_profile(profile, opt);
  for (ShImage& p : pages) scale_sh(p, pkg.iz_scale);
  const auto t0 = Clock::now();
  const double prior_seconds = sum_seconds(prior);
  ConversionRun run;
  run.result = convert_pages(pages, profile, opt);
  run.result.timings.insert(run.result.timings.begin(), prior.begin(), prior.end());
  return package(std::move(run), profile, opt, pkg, prior_seconds, t0);
}

ConversionRun run_transcode(const std::vector<FittedLevel>& levels, const Profile& profile, const PipelineOptions& opt,
                            const PackageOptions& pkg, std::vector<StageCost> prior) {
  const auto t0 = Clock::now();
  const double prior_seconds = sum_seconds(prior);
  ConversionRun run;
  run.result.timings = std::move(prior);
  return finish(std::move(run), levels, profile, opt, pkg, prior_seconds, t0);
}

}  // namespace ahd

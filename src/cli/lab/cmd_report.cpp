// ahdpack report …: the accuracy tables of docs/accuracy.md "Accuracy", each from one command anyone can rerun.
//   hard-cases  the fit and the quantised planes on the hard-case set
//   eps         the horizon rule's eps against error (how the default was chosen)
//   profiles    every profile end to end: bytes per texel, error vs the source SH, open vs closed loop
//   direction   I_z alone vs the full encoding as the directional part shrinks (--direction auto)
//   fit         linear vs refined direction fit (cmd_report_fit.cpp)
#include <cstdio>

#include "api/option_table.h"
#include "cli/commands.h"
#include "cli/report.h"
#include "cli/lab/svg_plot.h"
#include "files/output_set.h"
#include "files/profile_file.h"
#include "fit/direction_refine.h"
#include "image/sh_exr.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"
#include "lab/hard_cases.h"

namespace ahd::cli {

namespace {

// All hard cases in one image (sanitised as a reader would), for whole-set figures.
ShImage hard_case_image() {
  std::vector<HardCase> cases = hard_cases();
  size_t n = 0;
  for (const auto& c : cases) n += c.sh.texels();
  ShImage all = make_sh_image(int(n), 1, 9);
  size_t at = 0;
  for (auto& c : cases) {
    ReadStats rs;
    sanitise_sh(c.sh, false, &rs);
    for (size_t i = 0; i < c.sh.texels(); ++i, ++at) {
      std::copy(c.sh.texel(i), c.sh.texel(i) + 27, all.texel(at));
      all.coverage[at] = c.sh.coverage[i];
    }
  }
  return all;
}

// bytes per texel against the error along the normal (what quantisation adds; the hemisphere
// error is the AHD model's and nearly equal across profiles), one point per profile and set.
void report_profiles(int size, const std::string& plot_path) {
  Plot plot;
  plot.title = "Profiles: size against error (ahdpack report profiles)";
  plot.x_label = "bytes per texel";
  plot.y_label = "I_z relative error p99, closed loop";
  plot.note = "analytic scene " + std::to_string(size) + "x" + std::to_string(size) +
              " and the hard-case set; labels: profile (hemisphere relative RMSE, mean)";
  plot.series = {{"analytic scene", "point ours", "#1f77b4", 'o', {}}, {"hard-case set", "point ours", "#d62728", 's', {}}};
  BakerOptions bo;
  bo.width = bo.height = size;
  const ShImage sets[2] = {bake_analytic_scene(bo), hard_case_image()};
  const char* names[2] = {"analytic scene", "hard-case set"};
  std::printf("| profile | bytes/texel | set | loop | rel RMSE mean | rel p99 | rel max | log2 RMSE mean | log2 p99 | log2 max | I_z rel p99 | I_z rel max |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& name : list_profiles()) {
    const Profile p = load_profile(name);
    bool ok = true;
    for (PixelFormat f : {p.iz, p.dir, p.ratio, p.dirratio}) ok &= plane_format_supported(f);
    if (!ok) {
      std::printf("| %s | – | – | – | not available in this build | | | | | | | |\n", name.c_str());
      continue;
    }
    double bpt = 0;
    auto bytes = [](PixelFormat f) {
      const FormatInfo& i = format_info(f);
      return double(i.bytes_per_block) / (i.block_width * i.block_height);
    };
    bpt = bytes(p.iz) + (p.packed_dir_ratio ? bytes(p.dirratio) : bytes(p.dir) + bytes(p.ratio)) /
                            double(p.dir_ratio_scale * p.dir_ratio_scale);
    for (int s = 0; s < 2; ++s) {
      PipelineOptions opt;
      opt.measure = Measure::Full;
      if (p.ratio_rgb) opt.fit.ratio_form = RatioForm::Rgb;
      const PipelineResult r = run_conversion(sets[s], p, opt);
      for (int loop = 0; loop < 2; ++loop) {
        const ErrorReport& e = loop ? r.final_error : r.open_loop_error;
        std::printf("| %s | %.2f | %s | %s | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e |\n", name.c_str(), bpt,
                    names[s], loop ? "closed" : "open", e.relative.mean, e.relative.p99, e.relative.max, e.log2.mean,
                    e.log2.p99, e.log2.max, e.normal_rel.p99, e.normal_rel.max);
        char label[96];
        std::snprintf(label, sizeof label, "%s (%.3f)", name.c_str(), e.relative.mean);
        if (loop) plot.series[s].points.push_back({bpt, e.normal_rel.p99, label});
      }
    }
  }
  if (!plot_path.empty()) {
    write_file_atomic(plot_path, plot_svg(plot));
    std::printf("\nplot: %s\n", plot_path.c_str());
  }
}

// The analytic scene with its directional part (every coefficient but L0) scaled by `s`.
ShImage scaled_directional_part(const ShImage& sh, double s) {
  ShImage out = sh;
  for (size_t i = 0; i < out.texels(); ++i)
    for (int k = 3; k < out.coeffs * 3; ++k) out.texel(i)[k] *= float(s);
  return out;
}

// How the --direction auto threshold was chosen: as the directional part shrinks, the error of
// I_z alone against the error of the full encoding (8-bit direction and ratio planes).
void report_direction(int size, const std::string& profile_name) {
  BakerOptions bo;
  bo.width = bo.height = size;
  const ShImage scene = bake_analytic_scene(bo);
  const Profile p = load_profile(profile_name);
  std::printf("Analytic scene %dx%d, directional part (L1, L2) scaled by s; profile %s. Relative hemisphere RMSE vs "
              "the scaled SH, covered texels (mean / p99).\n\n", size, size, p.name.c_str());
  std::printf("| s | I_z alone mean | I_z alone p99 | with direction planes mean | with direction planes p99 | auto (threshold %.2g) |\n",
              kDefaultAmbientThreshold);
  std::printf("|---|---|---|---|---|---|\n");
  for (double s : {0.0, 0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0}) {
    PipelineOptions opt;
    opt.measure = Measure::Full;
    opt.measure_baselines = false;
    opt.direction = DirectionPlanes::Keep;
    const ShImage sh = scaled_directional_part(scene, s);
    PipelineResult r;
    const std::vector<FittedLevel> levels = fit_levels(sh, opt, &r);
    quantise_levels(levels, p, opt, &r);
    const ErrorReport a = ambient_only_error(levels[0], 0);
    std::printf("| %g | %.2e | %.2e | %.2e | %.2e | %s |\n", s, a.relative.mean, a.relative.p99, r.final_error.relative.mean,
                r.final_error.relative.p99, a.relative.p99 > kDefaultAmbientThreshold ? "keep" : "drop");
  }
}

}  // namespace

void add_report_command(CLI::App& app) {
  CLI::App* r = app.add_subcommand("report", "Accuracy reports");
  add_report_fit_command(r);
  add_report_truth_command(r);
  CLI::App* h = r->add_subcommand("hard-cases", "Fit and quantise the hard-case set; print the error table");
  auto profile = std::make_shared<std::string>("uncompressed");
  h->add_option("--profile", *profile, "Output profile");
  // The conversion's default fit (ConversionOptions, the option table), not the fit stage's own.
  const OptionRow& fit_row = option_row("direction_fit");
  auto dir_fit = std::make_shared<std::string>(fit_row.text(ConversionOptions{}));
  std::vector<std::string> fits;
  for (const OptionEnumValue& v : fit_row.values) fits.push_back(v.name);
  h->add_option("--direction-fit", *dir_fit, "The direction fit (default: the conversion's, " + *dir_fit + ")")
      ->check(CLI::IsMember(fits));
  h->callback([profile, dir_fit]() {
    const Profile p = load_profile(*profile);
    FitOptions fit;
    if (!parse_direction_fit(*dir_fit, &fit.direction_fit)) throw Error("--direction-fit must be 'linear' or 'refined'");
    std::printf("Hard cases, profile %s, direction fit %s. Errors vs the source SH over 64 hemisphere normals, relative "
                "to the texel's mean irradiance; I_z = error along the normal.\n\n", p.name.c_str(), dir_fit->c_str());
    std::printf("| case | texels | rules fired | fit rel mean | fit rel max | fit I_z max | LS rel mean | LS I_z max | "
                "LS negative texels | quantised rel max | quantised I_z max |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (HardCase& hc : hard_cases()) {
      ReadStats rs;
      sanitise_sh(hc.sh, false, &rs);
      PipelineOptions opt;
      opt.measure = Measure::Full;
      opt.threads = 1;
      opt.fit.direction_fit = fit.direction_fit;
      const PipelineResult res = run_conversion(hc.sh, p, opt);
      std::string rules;
      auto add = [&](const char* what, size_t n) {
        if (n) rules += (rules.empty() ? "" : ", ") + std::string(what) + " " + std::to_string(n);
      };
      add("no-direction", res.fit_stats.no_direction);
      add("horizon", res.fit_stats.dir_clamped);
      add("negative I_z", res.fit_stats.negative_iz);
      add("black", res.fit_stats.black);
      add("non-finite", rs.non_finite_texels);
      std::printf("| %s | %zu | %s | %.2e | %.2e | %.1e | %.2e | %.1e | %zu | %.2e | %.1e |\n", hc.name.c_str(),
                  hc.sh.texels(), rules.empty() ? "–" : rules.c_str(), res.fit_error.relative.mean,
                  res.fit_error.relative.max, res.fit_error.normal_rel.max, res.unconstrained_error.relative.mean,
                  res.unconstrained_error.normal_rel.max, res.unconstrained_error.negative, res.final_error.relative.max,
                  res.final_error.normal_rel.max);
    }
  });

  CLI::App* e = r->add_subcommand("eps", "Measure the horizon rule: error against eps on grazing light and the sample");
  auto eprofile = std::make_shared<std::string>("uncompressed");
  e->add_option("--profile", *eprofile, "Output profile");
  e->callback([eprofile]() {
    const Profile p = load_profile(*eprofile);
    BakerOptions bo;
    bo.width = bo.height = 128;
    const ShImage sets[2] = {grazing_light_set(64, 1), bake_analytic_scene(bo)};
    const char* names[2] = {"grazing-light set (64x64)", "analytic scene (128x128)"};
    for (int s = 0; s < 2; ++s) {
      std::printf("%s, profile %s: relative hemisphere RMSE vs SH (mean / p99 / max)\n", names[s], p.name.c_str());
      std::printf("  %-6s %-9s %-27s %-27s %-18s %s\n", "eps", "Cd<=Iz/e", "fit rel (mean p99 max)",
                  "quantised rel", "quantised log2", "tilted");
      for (double eps : {0.01, 0.02, 0.05, 0.1, 0.2, 0.3}) {
        PipelineOptions opt;
        opt.measure = Measure::Full;
        opt.fit.dz_min = eps;
        opt.measure_baselines = false;
        const PipelineResult res = run_conversion(sets[s], p, opt);
        std::printf("  %-6.2f %-9.0f %.2e %.2e %.2e   %.2e %.2e %.2e   %.2e %.2e    %zu\n", eps, 1.0 / eps,
                    res.fit_error.relative.mean, res.fit_error.relative.p99, res.fit_error.relative.max,
                    res.final_error.relative.mean, res.final_error.relative.p99, res.final_error.relative.max,
                    res.final_error.log2.mean, res.final_error.log2.p99, res.fit_stats.dir_clamped);
      }
    }
  });

  CLI::App* pr = r->add_subcommand("profiles", "Every profile end to end on the analytic scene and the hard-case set");
  auto psize = std::make_shared<int>(256);
  auto pplot = std::make_shared<std::string>();
  pr->add_option("--size", *psize, "Analytic scene size");
  pr->add_option("--plot", *pplot, "Also write bytes per texel against error as an SVG plot");
  pr->callback([psize, pplot]() { report_profiles(*psize, *pplot); });

  CLI::App* dr = r->add_subcommand("direction", "How --direction auto decides: I_z alone vs the full encoding as L1/L2 shrink");
  auto dsize = std::make_shared<int>(128);
  auto dprofile = std::make_shared<std::string>("pc-bc");
  dr->add_option("--size", *dsize, "Analytic scene size");
  dr->add_option("--profile", *dprofile, "Output profile");
  dr->callback([dsize, dprofile]() { report_direction(*dsize, *dprofile); });
}

}  // namespace ahd::cli

// ahdpack sample -o OUT.exr: writes the built-in analytic scene as a canonical SH EXR.
// ahdpack report hard-cases: the fit on the hard-case set, as the README's table.
#include <cstdio>

#include "cli/commands.h"
#include "cli/report.h"
#include "io/sh_exr.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"
#include "sample/hard_cases.h"

namespace ahd::cli {

void add_sample_command(CLI::App& app) {
  auto bo = std::make_shared<BakerOptions>();
  auto out = std::make_shared<std::string>();
  auto order = std::make_shared<int>(2);
  CLI::App* c = app.add_subcommand("sample", "Write the built-in analytic scene as a canonical SH EXR");
  c->add_option("-o,--output", *out, "Output EXR")->required();
  c->add_option("--size", bo->width, "Width and height")->check(CLI::Range(1, 16384));
  c->add_option("--order", *order, "SH order: 1 (L1) or 2 (L2)")->check(CLI::IsMember({1, 2}));
  c->add_option("--seed", bo->seed, "Scene seed (0 = canonical)");
  c->callback([bo, out, order]() {
    BakerOptions o = *bo;
    o.height = o.width;
    o.coeffs = *order == 1 ? 4 : 9;
    write_canonical_sh(*out, bake_analytic_scene(o));
    std::printf("ahdpack sample: %dx%d %s -> %s\n", o.width, o.height, o.coeffs == 9 ? "L2" : "L1", out->c_str());
  });

  CLI::App* r = app.add_subcommand("report", "Accuracy reports");
  CLI::App* h = r->add_subcommand("hard-cases", "Fit and quantise the hard-case set; print the error table");
  auto profile = std::make_shared<std::string>("uncompressed");
  h->add_option("--profile", *profile, "Output profile");
  h->callback([profile]() {
    const Profile p = load_profile(*profile);
    std::printf("hard cases, profile %s (per case: texels; error vs SH over 64 hemisphere normals)\n", p.name.c_str());
    print_error_header(stdout);
    for (HardCase& hc : hard_cases()) {
      ReadStats rs;
      sanitise_sh(hc.sh, false, &rs);
      ConvertOptions opt;
      opt.threads = 1;
      const ConvertResult res = convert(hc.sh, p, opt);
      std::printf("%s (%zu texels; rules: no-dir %zu, horizon %zu, neg I_z %zu, black %zu, non-finite %zu)\n",
                  hc.name.c_str(), res.fit_stats.covered, res.fit_stats.no_direction, res.fit_stats.dir_clamped,
                  res.fit_stats.negative_iz, res.fit_stats.black, rs.non_finite_texels);
      print_error_row(stdout, "fit: constrained AHD", res.fit_error);
      print_error_row(stdout, "fit: unconstrained LS", res.unconstrained_error);
      print_error_row(stdout, "quantised, closed loop", res.final_error);
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
        ConvertOptions opt;
        opt.fit.dz_min = eps;
        opt.measure_unconstrained = false;
        opt.measure_open_loop = false;
        const ConvertResult res = convert(sets[s], p, opt);
        std::printf("  %-6.2f %-9.0f %.2e %.2e %.2e   %.2e %.2e %.2e   %.2e %.2e    %zu\n", eps, 1.0 / eps,
                    res.fit_error.relative.mean, res.fit_error.relative.p99, res.fit_error.relative.max,
                    res.final_error.relative.mean, res.final_error.relative.p99, res.final_error.relative.max,
                    res.final_error.log2.mean, res.final_error.log2.p99, res.fit_stats.dir_clamped);
      }
    }
  });
}

}  // namespace ahd::cli

// ahdpack verify NAME.json --source IN [--layout …] [--normals …|--mesh …] [--max-rel-p99 X] [--max-log-rmse Y]
//   [--max-iz-rel-p99 Z] [--dark-floor K]: IN and the input options as convert takes them (bakers/bake_input.h)
// ahdpack verify NAME.json --golden OTHER.json [--max-diff-p99 X] [--max-diff-max Y]
// A check for users' CI: decodes a conversion (every plane's size and SHA-256 checked first) and
// compares it with the source SH or with a stored golden conversion. One line per check,
// "PASS|FAIL <check> <value> <= <bound>", then a summary; exit 0 when every check passes, 1 when
// any fails (bad input: one error line, exit 1, as everywhere).
//
// Default bounds (docs/tools.md "Verify in CI") pass every standard profile on the analytic
// sample and on a real Godot bake with a margin and catch a broken or swapped plane; a CI job should
// set its own from its lightmaps' measured figures. The relative errors against the source are
// floored at --dark-floor × the image's p99 irradiance (cli/source_error.h says why).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli/commands.h"
#include "cli/conversion_args.h"
#include "cli/conversion_view.h"
#include "cli/source_error.h"
#include "core/error.h"
#include "core/parallel.h"

namespace ahd::cli {

namespace {

struct VerifyArgs {
  std::string manifest, golden;
  BakeInput source;  // --source and the input options: what convert read
  double max_rel_p99 = 0.30, max_log_rmse = 0.15, max_iz_rel_p99 = 0.05;  // against the source
  double dark_floor = kDefaultDarkFloor;  // relative errors' denominators floored at this × the p99 (source_error.h)
  double max_diff_p99 = 0.01, max_diff_max = 0.10;                        // against a golden conversion
};

struct Checks {
  int failed = 0, total = 0;
  void check(const char* name, double value, double bound, const char* what) {
    const bool ok = value <= bound;  // NaN fails
    ++total;
    failed += !ok;
    std::printf("%s  %-16s %.4g <= %.4g  (%s)\n", ok ? "PASS" : "FAIL", name, value, bound, what);
  }
};

// Per texel of every level and page: RMS over 64 hemisphere normals and the channels of the
// difference of the two decoded irradiances, over the golden's mean luminance (floored at 1e-4 of
// its p99, so black texels do not divide by zero).
std::vector<double> golden_differences(const std::string& a, const std::string& b, uint32_t layers) {
  const double luma[3] = {0.2126, 0.7152, 0.0722};
  const int nd = 64;
  const std::vector<double> dirs = hemisphere_directions(nd);
  std::vector<double> out;
  for (uint32_t layer = 0; layer < layers; ++layer) {
    const ConversionView va = read_conversion(a, int(layer)), vb = read_conversion(b, int(layer));
    for (size_t l = 0; l < va.levels.size(); ++l) {
      const std::vector<AhdLobe> la = lobes_from_planes(va.levels[l], va.manifest.dz_min);
      const std::vector<AhdLobe> lb = lobes_from_planes(vb.levels[l], vb.manifest.dz_min);
      std::vector<double> rms(la.size()), lum(la.size());
      parallel_for(la.size(), 0, 256, [&](size_t i) {
        double se = 0, sl = 0;
        for (int k = 0; k < nd; ++k) {
          const double* w = &dirs[size_t(k) * 3];
          const double ca = std::max(0.0, w[0] * la[i].d[0] + w[1] * la[i].d[1] + w[2] * la[i].d[2]);
          const double cb = std::max(0.0, w[0] * lb[i].d[0] + w[1] * lb[i].d[1] + w[2] * lb[i].d[2]);
          for (int c = 0; c < 3; ++c) {
            const double ea = la[i].ca[c] + ca * la[i].cd[c], eb = lb[i].ca[c] + cb * lb[i].cd[c];
            se += (ea - eb) * (ea - eb);
            sl += luma[c] * eb;
          }
        }
        rms[i] = std::sqrt(se / (3.0 * nd));
        lum[i] = sl / nd;
      });
      std::vector<double> sorted = lum;
      std::sort(sorted.begin(), sorted.end());
      const double floor = 1e-4 * (sorted.empty() ? 0.0 : sorted[size_t(0.99 * double(sorted.size() - 1))]);
      for (size_t i = 0; i < rms.size(); ++i) {
        const double d = std::max(lum[i], floor);
        out.push_back(d > 0 ? rms[i] / d : (rms[i] > 0 ? INFINITY : 0.0));
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

void run_verify(const VerifyArgs& a) {
  if (a.source.input.empty() == a.golden.empty())
    throw Error("verify needs either --source IN (and convert's input options) or --golden OTHER.json");
  Checks c;
  const ConversionView v = read_conversion(a.manifest);
  if (!a.source.input.empty()) {
    std::string described;
    const std::vector<ShImage> pages = read_source_for(a.source, v.manifest, &described);
    for (size_t p = 0; p < pages.size(); ++p) {
      const ConversionView layer = p == 0 ? ConversionView{} : read_conversion(a.manifest, int(p));
      const ConversionView& lv = p == 0 ? v : layer;
      const SourceErrorFigures e = measure_against_source(pages[p], lv.levels[0], v.manifest.dz_min, a.dark_floor);
      const std::string page = pages.size() > 1 ? " page " + std::to_string(p) : "";
      std::printf(
          "ahdpack verify: %s%s against %s (level 0, %zu covered texels; floor %.3g x p99 E = %.4g: %zu texels "
          "below it)\n",
          a.manifest.c_str(), page.c_str(), described.c_str(), e.texels, a.dark_floor, a.dark_floor * e.scale,
          e.floored);
      c.check("rel-p99", e.rel_p99, a.max_rel_p99,
              "hemisphere RMSE / max(mean E, floor x p99), 99th percentile over texels");
      c.check("log-rmse", e.log_rmse, a.max_log_rmse, "mean over texels of the log2(1+E) RMSE over the hemisphere");
      c.check("iz-rel-p99", e.iz_rel_p99, a.max_iz_rel_p99,
              "error along the normal / max(E(z), floor x p99), 99th percentile");
    }
  } else {
    const ConversionView g = read_conversion(a.golden);
    const Manifest &m = v.manifest, &gm = g.manifest;
    std::printf("ahdpack verify: %s against the golden %s\n", a.manifest.c_str(), a.golden.c_str());
    std::string differs;
    if (m.width != gm.width || m.height != gm.height) differs += " size";
    if (m.levels != gm.levels) differs += " levels";
    if (m.layers != gm.layers) differs += " pages";
    if (m.profile != gm.profile) differs += " profile";
    if (m.directional != gm.directional) differs += " direction-planes";
    if (m.ratio_form != gm.ratio_form) differs += " ratio-form";
    ++c.total;
    if (!differs.empty()) {
      ++c.failed;
      std::printf("FAIL  %-16s differs:%s\n", "golden-layout", differs.c_str());
    } else {
      std::printf("PASS  %-16s same size, levels, pages, profile, planes\n", "golden-layout");
      const std::vector<double> d = golden_differences(a.manifest, a.golden, m.layers);
      const double p99 = d.empty() ? 0 : d[std::min(d.size() - 1, size_t(std::ceil(0.99 * double(d.size()))) - 1)];
      c.check("golden-diff-p99", p99, a.max_diff_p99, "relative difference of decoded irradiance, every level, p99");
      c.check("golden-diff-max", d.empty() ? 0 : d.back(), a.max_diff_max, "the same, largest texel");
    }
  }
  std::printf("ahdpack verify: %d of %d checks passed\n", c.total - c.failed, c.total);
  std::fflush(stdout);
  if (c.failed) throw CLI::RuntimeError(1);  // exit 1 without another line: the FAIL lines say why
}

}  // namespace

void add_verify_command(CLI::App& app) {
  auto a = std::make_shared<VerifyArgs>();
  CLI::App* c = app.add_subcommand("verify", "Check a conversion against its source SH or a golden conversion "
                                             "within bounds (exit 0 = pass, 1 = fail); for CI jobs");
  c->add_option("manifest", a->manifest, "NAME.json written by convert")->required();
  c->add_option("--source", a->source.input,
                "The source SH as convert read it: the canonical EXR or any file of a baker's set (with the same "
                "--layout, --normals, --mesh… as the conversion)");
  add_input_options(c, &a->source);
  c->add_option("--dark-floor", a->dark_floor,
                "Source: the relative errors' denominator is at least this fraction of the source's p99 irradiance, "
                "so near-black texels are judged by their absolute error (default 0.03; 0 = per-texel relative)")
      ->check(CLI::Range(0.0, 1.0));
  c->add_option("--golden", a->golden, "A stored conversion (its manifest) to compare with");
  c->add_option("--max-rel-p99", a->max_rel_p99, "Bound of the hemisphere relative RMSE p99 (default 0.30)");
  c->add_option("--max-log-rmse", a->max_log_rmse, "Bound of the mean log2 RMSE (default 0.15)");
  c->add_option("--max-iz-rel-p99", a->max_iz_rel_p99, "Bound of the relative error along the normal, p99 (default 0.05)");
  c->add_option("--max-diff-p99", a->max_diff_p99, "Golden: bound of the relative difference p99 (default 0.01)");
  c->add_option("--max-diff-max", a->max_diff_max, "Golden: bound of the largest relative difference (default 0.10)");
  c->callback([a]() { run_verify(*a); });
}

}  // namespace ahd::cli

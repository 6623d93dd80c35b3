// ahdpack report truth DIR…: every representation against path-traced lighting (truth_set.h). The
// training normals make a baker-like L2 SH lightmap; each representation is decoded at the held-out
// normals (and at a bumpy normal-mapped normal field) and compared with what Cycles computed there.
// Error: relative L1, Σ|I − E| / Σ|E| over covered texels, normals and RGB.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <ahd/convert.h>

#include "cli/commands.h"
#include "cli/lab/truth_plot.h"
#include "core/option_enums.h"
#include "lab/truth_baker_formats.h"
#include "lab/truth_reference.h"
#include "lab/truth_file.h"
#include "fit/ahd_decode.h"
#include "fit/ahd_fit.h"
#include "fit/fit_image.h"
#include "lab/fit_quality.h"
#include "files/output_set.h"
#include "files/profile_file.h"
#include "pipeline/convert.h"
#include "sh/sh_image.h"
#include "files/utf8_path.h"

namespace ahd::cli {

namespace {

// A representation: its irradiance for texel i and tangent-space normal n.
using Eval = TruthEval;

Eval sh_eval(const ShImage& sh) {
  return [&sh](size_t i, const double n[3], double out[3]) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    for (int c = 0; c < 3; ++c) out[c] = eval_irradiance(p[c], n);
  };
}

Eval plain_eval(const ShImage& sh) {
  return [&sh](size_t i, const double*, double out[3]) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const double z[3] = {0, 0, 1};
    for (int c = 0; c < 3; ++c) out[c] = std::max(0.0, eval_irradiance(p[c], z));
  };
}

// The decoded planes halfway between texels i and j (each plane averaged; d unnormalised, as
// decode_irradiance and the shaders normalise it after the filter).
TruthPairEval planes_pair_eval(const DecodedPlanes& p, double dz_min) {
  return [&p, dz_min](size_t i, size_t j, const double n[3], double out[3]) {
    float m[9];
    truth_mid_planes(p.iz.data(), p.d.data(), p.ratio.data(), i, j, 3, m);
    decode_irradiance(m, m + 3, m + 6, n, dz_min, out);
  };
}

Eval planes_eval(const DecodedPlanes& p, double dz_min) {
  return [&p, dz_min](size_t i, const double n[3], double out[3]) {
    decode_irradiance(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], n, dz_min, out);
  };
}

double level0_bytes_per_texel(const PipelineResult& r) {
  double bytes = 0;
  for (const Plane& p : r.planes) bytes += double(p.texture.levels[0].data.size());
  return bytes / double(r.planes[0].texture.levels[0].width * r.planes[0].texture.levels[0].height);
}

struct Row {
  std::string name;
  double bytes;
  TruthErrors err;
  double p99 = -1;
  double between = -1;  // truth_between_error, where the representation filters as planes or SH
  enum Kind { Reference, Anchor, Default, Other } kind = Reference;  // Anchor: an engine's shipped format
};

// Each engine anchor's budget against ahdpack's default-fit profiles of no more bytes: the best of
// them, and whether its held-out error is lower (issue 43's "every byte budget").
void print_budgets(const std::vector<Row>& rows) {
  std::printf("\nAt each anchor's bytes, the best ahdpack profile (default fit) of no more bytes:\n\n");
  std::printf("| anchor | bytes/texel | its error | ahdpack | bytes/texel | error | lower |\n|---|---|---|---|---|---|---|\n");
  for (const Row& a : rows) {
    if (a.kind != Row::Anchor) continue;
    const Row* best = nullptr;
    for (const Row& r : rows)
      if (r.kind == Row::Default && r.bytes <= a.bytes + 1e-9 && (!best || r.err.held_out < best->err.held_out)) best = &r;
    if (!best) {
      std::printf("| %s | %.3f | %.4f | — | — | — | no profile |\n", a.name.c_str(), a.bytes, a.err.held_out);
      continue;
    }
    std::printf("| %s | %.3f | %.4f | %s | %.3f | %.4f | %s |\n", a.name.c_str(), a.bytes, a.err.held_out, best->name.c_str(),
                best->bytes, best->err.held_out, best->err.held_out < a.err.held_out ? "yes" : "NO");
  }
}

void print_rows(const TruthSet& t, const std::vector<Row>& rows) {
  std::printf("\n%s (%d² texels, %zu held-out normals):\n\n", t.name.c_str(), t.width,
              size_t(std::count(t.held_out.begin(), t.held_out.end(), 1)));
  std::printf("| representation | bytes/texel (level 0) | held-out normals | normal-mapped | between texels | neighbour angle p99 (°) |\n|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    std::printf("| %s | %s | %.4f | %.4f | %s | %s |\n", r.name.c_str(), r.bytes > 0 ? std::to_string(r.bytes).substr(0, 5).c_str() : "—",
                r.err.held_out, r.err.bumped, r.between >= 0 ? std::to_string(r.between).substr(0, 6).c_str() : "–",
                r.p99 >= 0 ? std::to_string(r.p99).substr(0, 5).c_str() : "–");
  }
}

void report_truth(const std::vector<std::string>& dirs, const std::vector<std::string>& profiles, int search, double guard,
                  int window, double coherence, const std::string& plot) {
  for (const std::string& dir : dirs) {
    TruthSet t = load_truth_set(dir);
    // Named by its folder (the corpus has two bakes of one scene at different sizes).
    std::filesystem::path fp = fs_path(dir).lexically_normal();
    if (fp.filename().empty()) fp = fp.parent_path();  // "…/area/"
    const std::string folder = utf8_string(fp.filename());
    if (!folder.empty() && folder != "." && folder != "..") t.name = folder;
    const ShImage l2 = baker_sh(t, 9, 0);
    ShImage l1 = make_sh_image(t.width, t.height, 4);
    l1.coverage = l2.coverage;
    for (size_t i = 0; i < t.texels(); ++i)
      for (int k = 0; k < 12; ++k) l1.texel(i)[k] = l2.texel(i)[k];
    std::vector<Row> rows;
    rows.push_back({"L2 SH, float", 108, truth_errors(t, sh_eval(l2)), -1, truth_between_error(t, mean_of_pair(sh_eval(l2)))});
    rows.push_back({"L1 SH (the same SH truncated), float", 48, truth_errors(t, sh_eval(l1)), -1,
                    truth_between_error(t, mean_of_pair(sh_eval(l1)))});
    rows.push_back({"plain lightmap (I_z only), float", 0, truth_errors(t, plain_eval(l2)), -1,
                    truth_between_error(t, mean_of_pair(plain_eval(l2)))});
    // The bakers' own directional formats from the same SH's L1 part, at their shipped bytes.
    for (bool q : {false, true}) {
      for (const BakerFormatEval& f : baker_formats(l2, q))
        rows.push_back({f.label, f.bytes_per_texel, truth_errors(t, f.eval), -1, -1,
                        f.bytes_per_texel > 0 ? Row::Anchor : Row::Reference});
    }
    FitOptions lum;
    lum.pair_guard_deg = guard;
    if (window >= 0) lum.direction_window = window;
    if (coherence >= 0) lum.coherence_tolerance = coherence;
    for (const EnumName<DirectionFit>& df : kDirectionFits) {
      FitOptions o = lum;
      o.direction_fit = df.value;
      const AhdImage a = fit_image(l2, o, 0);
      rows.push_back({std::string("AHD float, ") + df.name + " d", 0,
                      truth_errors(t, ahd_image_eval(a, o.dz_min)), direction_p99_angle_deg(a),
                      truth_between_error(t, ahd_image_pair_eval(a, o.dz_min))});
    }
    const AhdImage bf = searched_direction_fit(l2, lum, search);
    rows.push_back({"constrained AHD float, d searched per texel (" + std::to_string(search) + " directions)", 0,
                    truth_errors(t, ahd_image_eval(bf, lum.dz_min)), direction_p99_angle_deg(bf),
                    truth_between_error(t, ahd_image_pair_eval(bf, lum.dz_min))});
    for (const std::string& name : profiles) {
      for (const EnumName<DirectionFit>& df : kDirectionFits) {
        const Profile prof = load_profile(name);
        PipelineOptions opt;
        opt.fit.direction_fit = df.value;
        opt.fit.pair_guard_deg = guard;
        if (window >= 0) opt.fit.direction_window = window;
        if (coherence >= 0) opt.fit.coherence_tolerance = coherence;
        opt.fit.ratio_form = prof.ratio_rgb ? RatioForm::Rgb : RatioForm::Luminance;
        opt.max_levels = 1;
        opt.direction = DirectionPlanes::Keep;
        const PipelineResult r = run_conversion(l2, prof, opt);
        const DecodedPlanes p = decode_planes(r.planes, prof.ratio_rgb, 0);
        rows.push_back({"ahdpack " + name + ", " + df.name + " d",
                        level0_bytes_per_texel(r), truth_errors(t, planes_eval(p, opt.fit.dz_min)), -1,
                        truth_between_error(t, planes_pair_eval(p, opt.fit.dz_min)),
                        df.value == ConversionOptions{}.direction_fit ? Row::Default : Row::Other});
      }
    }
    print_rows(t, rows);
    print_budgets(rows);
    if (!plot.empty()) {
      std::vector<TruthPlotRow> points;
      for (const Row& r : rows) points.push_back({r.name, r.bytes, r.err.held_out});
      const std::string path = truth_plot_path(plot, t.name, dirs.size());
      write_file_atomic(path, truth_plot_svg(t.name, points));
      std::printf("\nplot: %s\n", path.c_str());
    }
  }
}

}  // namespace

void add_report_truth_command(CLI::App* report) {
  CLI::App* c = report->add_subcommand("truth", "Every representation against path-traced lighting (tests/data/truth/*)");
  auto dirs = std::make_shared<std::vector<std::string>>();
  auto profiles = std::make_shared<std::vector<std::string>>(std::vector<std::string>{"pc-bc", "pc-bc-half", "pc-bc-quarter", "uncompressed"});
  auto search = std::make_shared<int>(300);
  auto guard = std::make_shared<double>(FitOptions{}.pair_guard_deg);
  auto plot = std::make_shared<std::string>();
  c->add_option("DIR", *dirs, "Reference folders (truth.json + truth.bin, scripts/truth/bake_truth.py)")->required();
  c->add_option("--profiles", *profiles, "Profiles to convert with");
  c->add_option("--search", *search, "Directions of the per-texel brute-force search")->check(CLI::Range(1, 100000));
  c->add_option("--guard", *guard, "Refined: pair guard angle T in degrees (0 = off)")->check(CLI::Range(0.0, 90.0));
  auto window = std::make_shared<int>(-1);
  c->add_option("--window", *window, "Refined: direction window radius (default: the fit's own)")->check(CLI::Range(0, 8));
  auto coherence = std::make_shared<double>(-1);
  c->add_option("--coherence", *coherence, "Refined, per texel: coherence tolerance (default: the fit's own)")->check(CLI::Range(0.0, 1.0));
  c->add_option("--plot", *plot, "Also plot error against bytes per texel: OUT.svg, or a folder (one SVG per scene)");
  c->callback([dirs, profiles, search, guard, window, coherence, plot]() {
    report_truth(*dirs, *profiles, *search, *guard, *window, *coherence, *plot);
  });
}

}  // namespace ahd::cli

#include "pipeline/report_json.h"

namespace ahd {

nlohmann::json error_json(const ErrorReport& e) {
  auto stat = [](const ErrorStat& s) { return nlohmann::json{{"mean", s.mean}, {"p99", s.p99}, {"max", s.max}}; };
  return {{"texels", e.texels},         {"rmse", stat(e.rmse)},           {"relative", stat(e.relative)},
          {"log2", stat(e.log2)},       {"iz_relative", stat(e.normal_rel)}, {"negative_texels", e.negative}};
}

namespace {

nlohmann::json fit_rules_json(const FitStats& s) {
  return {{"texels", s.texels},           {"covered", s.covered},         {"no_direction", s.no_direction},
          {"horizon_tilted", s.dir_clamped}, {"negative_iz", s.negative_iz}, {"black", s.black},
          {"horizon_tilted_or_negative_iz_fraction", rules_share(s)}};
}

// The input's L1 figures (pipeline/sh_input_check.h), per layer y, z, x.
nlohmann::json input_sh_json(const L1Figures& f) {
  nlohmann::json neg = nlohmann::json::array(), zero = nlohmann::json::array(), n = nlohmann::json::array();
  for (int k = 0; k < 3; ++k) {
    const double v = double(f.values[k]);
    n.push_back(f.values[k]);
    neg.push_back(v > 0 ? double(f.negative[k]) / v : 0.0);
    zero.push_back(v > 0 ? double(f.zero[k]) / v : 0.0);
  }
  return {{"l1_layers", {"y", "z", "x"}}, {"l1_values", n}, {"l1_negative_fraction", neg}, {"l1_zero_fraction", zero}};
}

// What one page (or the whole conversion) says about its input and fit.
void add_figures(const PipelineResult& r, nlohmann::json* j) {
  (*j)["fit_rules"] = fit_rules_json(r.fit_stats);
  if (r.l1.measured()) (*j)["input_sh"] = input_sh_json(r.l1);
  (*j)["warnings"] = r.warnings;
}

}  // namespace

nlohmann::json convert_report_json(const PipelineResult& r, double total_seconds) {
  nlohmann::json j;
  add_figures(r, &j);
  j["error"] = {{"fit", error_json(r.fit_error)},
                {"unconstrained_ls", error_json(r.unconstrained_error)},
                {"quantised_open_loop", error_json(r.open_loop_error)},
                {"quantised_closed_loop", error_json(r.final_error)}};
  j["codec"] = {{"clamped", r.codec_stats.clamped}, {"non_finite", r.codec_stats.non_finite}};
  j["direction"] = {{"planes", r.directional ? "kept" : "dropped"}, {"reason", r.direction_reason}};
  if (r.ambient_error.texels) j["direction"]["iz_only_error"] = error_json(r.ambient_error);
  nlohmann::json levels = nlohmann::json::array();
  for (size_t l = 0; l < r.level_error.size(); ++l) {
    nlohmann::json e = error_json(r.level_error[l]);
    if (l < r.dilate_stats.size())
      e["dilation"] = {{"covered", r.dilate_stats[l].covered}, {"guard", r.dilate_stats[l].guard},
                       {"filled", r.dilate_stats[l].filled}, {"rings", r.dilate_stats[l].rings},
                       {"far", r.dilate_stats[l].far}};
    levels.push_back(e);
  }
  j["levels"] = levels;
  if (!r.pages.empty()) {  // an atlas: the figures above are every page's totals; each page's own here
    nlohmann::json pages = nlohmann::json::array();
    for (size_t p = 0; p < r.pages.size(); ++p) {
      const PipelineResult& pr = r.pages[p];
      nlohmann::json pj = {{"page", p}};
      add_figures(pr, &pj);
      pj["error"] = {{"fit", error_json(pr.fit_error)}, {"quantised_closed_loop", error_json(pr.final_error)}};
      pj["direction"] = {{"planes", pr.directional ? "kept" : "dropped"}, {"reason", pr.direction_reason}};
      if (pr.ambient_error.texels) pj["direction"]["iz_only_error"] = error_json(pr.ambient_error);
      pj["codec"] = {{"clamped", pr.codec_stats.clamped}, {"non_finite", pr.codec_stats.non_finite}};
      pages.push_back(pj);
    }
    j["pages"] = pages;
  }
  nlohmann::json t = nlohmann::json::object();
  for (const auto& s : r.timings) t[s.stage] = s.seconds;
  t["total"] = total_seconds;
  j["seconds"] = t;
  return j;
}

}  // namespace ahd

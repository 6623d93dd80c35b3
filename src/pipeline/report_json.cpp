#include "pipeline/report_json.h"

namespace ahd {

nlohmann::json error_json(const ErrorReport& e) {
  auto stat = [](const ErrorStat& s) { return nlohmann::json{{"mean", s.mean}, {"p99", s.p99}, {"max", s.max}}; };
  return {{"texels", e.texels},         {"rmse", stat(e.rmse)},           {"relative", stat(e.relative)},
          {"log2", stat(e.log2)},       {"iz_relative", stat(e.normal_rel)}, {"negative_texels", e.negative}};
}

nlohmann::json convert_report_json(const PipelineResult& r, double total_seconds) {
  nlohmann::json j;
  j["fit_rules"] = {{"texels", r.fit_stats.texels},           {"covered", r.fit_stats.covered},
                    {"no_direction", r.fit_stats.no_direction}, {"horizon_tilted", r.fit_stats.dir_clamped},
                    {"negative_iz", r.fit_stats.negative_iz},   {"black", r.fit_stats.black}};
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
  nlohmann::json t = nlohmann::json::object();
  for (const auto& s : r.timings) t[s.stage] = s.seconds;
  t["total"] = total_seconds;
  j["seconds"] = t;
  return j;
}

}  // namespace ahd

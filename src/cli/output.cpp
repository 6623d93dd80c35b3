#include "cli/output.h"

#include <cstdio>
#include <regex>

#include "cli/report.h"
#include "containers/container.h"
#include "files/file_io.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "files/manifest_file.h"
#include "files/output_set.h"
#include "files/utf8_path.h"

namespace ahd::cli {
namespace fs = std::filesystem;

void print_conversion(const std::string& source, const OutputPaths& out, const ConversionRun& run, bool closed_loop,
                      size_t non_finite_inputs) {
  const Manifest& m = run.output.manifest;
  const PipelineResult& r = run.result;
  std::printf("ahdpack: %s\n", source.c_str());
  std::printf("profile %s, %u mip level(s) -> %s\n", m.profile.c_str(), m.levels, out.sibling(".json").c_str());
  for (const auto& p : m.planes)
    std::printf("  %-9s %-12s %ux%u  %8llu bytes  %s\n", p.name.c_str(), format_info(p.format).name, p.width, p.height,
                (unsigned long long)p.bytes, utf8_string(out.dir / fs_path(p.file)).c_str());
  std::printf("  report    %s\n", out.sibling(".report.json").c_str());
  std::printf("direction and ratio planes %s\n", r.direction_reason.c_str());
  const FitStats& s = r.fit_stats;
  if (s.texels) {
    std::printf("fit: %zu covered of %zu texels; rules fired: no direction %zu, horizon-tilted %zu, negative I_z %zu, black %zu",
                s.covered, s.texels, s.no_direction, s.dir_clamped, s.negative_iz, s.black);
    if (non_finite_inputs) std::printf(", non-finite input texels zeroed %zu", non_finite_inputs);
    if (!r.pages.empty()) std::printf(" (all %zu pages)", r.pages.size());
    std::printf("\n");
  }
  for (size_t p = 0; p < r.pages.size(); ++p) {  // an atlas: the lines above are totals, each page here
    const PipelineResult& pr = r.pages[p];
    std::printf("  page %zu: %zu covered; horizon-tilted %zu, negative I_z %zu, black %zu; direction %s", p,
                pr.fit_stats.covered, pr.fit_stats.dir_clamped, pr.fit_stats.negative_iz, pr.fit_stats.black,
                pr.directional ? "kept" : "dropped");
    if (pr.final_error.texels) std::printf("; relative error mean %.2e, p99 %.2e", pr.final_error.relative.mean, pr.final_error.relative.p99);
    std::printf("\n");
  }

  if (!r.dilate_stats.empty())
    std::printf("dilation: %zu guard texels around the charts, %zu texels filled in %d rings, %zu beyond them set "
                "to 0 (level 0)\n",
                r.dilate_stats[0].guard, r.dilate_stats[0].filled - r.dilate_stats[0].far, r.dilate_stats[0].rings,
                r.dilate_stats[0].far);
  if (r.codec_stats.clamped || r.codec_stats.non_finite)
    std::printf("codec: %zu values clamped to the format's range (negative, or above its largest value: half "
                "float 65504, BC6H/RGB9E5 about as much), %zu non-finite; bright I_z that clamps is stored smaller "
                "with --iz-scale E/pi (or a factor)\n",
                r.codec_stats.clamped, r.codec_stats.non_finite);
  if (r.final_error.texels == 0) {
    std::printf("error: not measured (--measure estimate or full)\n");
  } else {
    const ErrorReport& e0 = r.final_error;
    if (e0.population > e0.texels)
      std::printf("error vs source SH irradiance (64 normals over the hemisphere), estimated from a fixed sample of %zu of "
                  "%zu covered texels per level (--measure full: every texel):\n", e0.texels, e0.population);
    else
      std::printf("error vs source SH irradiance (64 normals over the hemisphere, covered texels):\n");
    print_error_header(stdout);
    if (r.fit_error.texels) {
      print_error_row(stdout, "fit: constrained AHD", r.fit_error);
      if (r.unconstrained_error.texels) print_error_row(stdout, "fit: unconstrained LS", r.unconstrained_error);
    }
    if (closed_loop && r.open_loop_error.texels) print_error_row(stdout, "quantised, open loop", r.open_loop_error);
    print_error_row(stdout, closed_loop ? "quantised, closed loop" : "quantised (open loop)", r.final_error);
    for (size_t l = 1; l < r.level_error.size(); ++l) {
      const std::string label = "  mip " + std::to_string(l);
      print_error_row(stdout, label.c_str(), r.level_error[l]);
    }
  }
  std::printf("time:");
  for (const auto& t : r.timings) std::printf(" %s %.3f s,", t.stage.c_str(), t.seconds);
  std::printf(" total %.3f s\n", run.seconds);
}

}  // namespace ahd::cli

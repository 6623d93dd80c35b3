#include "cli/output.h"

#include <cstdio>

#include "cli/report.h"
#include "containers/sha256.h"
#include "io/image_io.h"
#include "io/output_set.h"

namespace ahd::cli {
namespace fs = std::filesystem;

OutputPaths output_paths(const std::string& out) {
  OutputPaths p;
  p.kind = container_kind_from_path(out);
  p.ext = p.kind == ContainerKind::KTX2 ? "ktx2" : "dds";
  p.dir = fs::path(out).parent_path();
  p.name = fs::path(out).stem().string();
  return p;
}

Manifest write_conversion(const OutputPaths& out, ConvertResult& r, const Profile& profile, const FitOptions& fit,
                          bool world_frame, bool zstd, const nlohmann::json& report_extra, double total_seconds) {
  Manifest m;
  m.profile = profile.name;
  m.container = out.ext;
  m.width = r.planes.at(0).texture.levels.at(0).width;
  m.height = r.planes.at(0).texture.levels.at(0).height;
  m.levels = uint32_t(r.planes.at(0).texture.levels.size());
  m.ratio_form = fit.ratio_form;
  m.dz_min = fit.dz_min;
  for (int i = 0; i < 3; ++i) m.luma[i] = fit.luma[i];
  m.direction_frame = world_frame ? "normal-frame" : "tangent";
  m.directional = r.directional;
  std::vector<OutputFile> files;
  for (Plane& p : r.planes) {
    p.texture.metadata = plane_metadata(m, p.name);
    std::vector<uint8_t> bytes = encode_container(out.kind, p.texture, zstd);
    // Content-addressed names: a new set never overwrites the planes the old manifest names.
    const std::string file = plane_file_name(out.name, p.name, out.ext, bytes);
    files.push_back({(out.dir / file).string(), std::move(bytes)});
    ManifestPlane mp;
    mp.name = p.name;
    mp.file = file;
    mp.format = p.texture.format;
    mp.width = p.texture.levels[0].width;
    mp.height = p.texture.levels[0].height;
    mp.levels = uint32_t(p.texture.levels.size());
    mp.bytes = files.back().bytes.size();
    mp.sha256 = sha256_hex(files.back().bytes.data(), files.back().bytes.size());
    m.planes.push_back(mp);
  }
  const std::string manifest_text = manifest_to_json(m);
  nlohmann::json report = convert_report_json(r, total_seconds);
  report["profile"] = profile.name;
  for (auto it = report_extra.begin(); it != report_extra.end(); ++it) report[it.key()] = *it;
  const std::string report_text = report.dump(2) + "\n";
  // The manifest last: renaming it publishes the set (io/output_set.h).
  files.push_back({out.sibling(".report.json"), std::vector<uint8_t>(report_text.begin(), report_text.end())});
  files.push_back({out.sibling(".json"), std::vector<uint8_t>(manifest_text.begin(), manifest_text.end())});
  publish_output_set(files, superseded_planes(out.dir.string(), out.name, files));
  return m;
}

void print_conversion(const std::string& source, const OutputPaths& out, const Manifest& m, const ConvertResult& r,
                      bool closed_loop, size_t non_finite_inputs, double total_seconds) {
  std::printf("ahdpack: %s\n", source.c_str());
  std::printf("profile %s, %u mip level(s) -> %s\n", m.profile.c_str(), m.levels, out.sibling(".json").c_str());
  for (const auto& p : m.planes)
    std::printf("  %-9s %-12s %ux%u  %8llu bytes  %s\n", p.name.c_str(), format_info(p.format).name, p.width, p.height,
                (unsigned long long)p.bytes, (out.dir / p.file).string().c_str());
  std::printf("  report    %s\n", out.sibling(".report.json").c_str());
  std::printf("direction and ratio planes %s\n", r.direction_reason.c_str());
  const FitStats& s = r.fit_stats;
  if (s.texels) {
    std::printf("fit: %zu covered of %zu texels; rules fired: no direction %zu, horizon-tilted %zu, negative I_z %zu, black %zu",
                s.covered, s.texels, s.no_direction, s.dir_clamped, s.negative_iz, s.black);
    if (non_finite_inputs) std::printf(", non-finite input texels zeroed %zu", non_finite_inputs);
    std::printf("\n");
  }
  if (!r.dilate_stats.empty())
    std::printf("dilation: %zu guard texels around the charts, %zu texels filled in %d rings (level 0)\n",
                r.dilate_stats[0].guard, r.dilate_stats[0].filled, r.dilate_stats[0].rings);
  if (r.codec_stats.clamped || r.codec_stats.non_finite)
    std::printf("codec: %zu values clamped to the format's range, %zu non-finite\n", r.codec_stats.clamped,
                r.codec_stats.non_finite);
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
  std::printf("time:");
  for (const auto& t : r.timings) std::printf(" %s %.3f s,", t.stage.c_str(), t.seconds);
  std::printf(" total %.3f s\n", total_seconds);
}

}  // namespace ahd::cli

#include "pipeline/package.h"

#include "containers/container.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "core/option_enums.h"
#include "pipeline/report_json.h"

namespace ahd {

namespace {

std::string plane_file_name_of_digest(const std::string& name, const std::string& plane, const std::string& ext,
                                      const std::string& sha256) {
  return name + "." + plane + "." + sha256.substr(0, 12) + "." + ext;
}

}  // namespace

std::string plane_file_name(const std::string& name, const std::string& plane, const std::string& ext,
                            const std::vector<uint8_t>& bytes) {
  return plane_file_name_of_digest(name, plane, ext, sha256_hex(bytes.data(), bytes.size()));
}

const char* container_extension(ContainerKind kind) { return kind == ContainerKind::KTX2 ? "ktx2" : "dds"; }

PackagedConversion package_conversion(PipelineResult& r, const Profile& profile, const FitOptions& fit,
                                      const PackageOptions& opt, double total_seconds) {
  const std::string ext = container_extension(opt.container);
  PackagedConversion out;
  Manifest& m = out.manifest;
  m.profile = profile.name;
  m.container = ext;
  m.width = r.planes.at(0).texture.levels.at(0).width;
  m.height = r.planes.at(0).texture.levels.at(0).height;
  m.levels = uint32_t(r.planes.at(0).texture.levels.size());
  m.layers = r.planes.at(0).texture.layers;  // atlas pages (pipeline/pages.h)
  m.ratio_form = fit.ratio_form;
  m.dz_min = fit.dz_min;
  for (int i = 0; i < 3; ++i) m.luma[i] = fit.luma[i];
  m.direction_frame = opt.world_frame ? "normal-frame" : "tangent";
  m.iz_scale = opt.iz_scale;
  m.directional = r.directional;
  m.instances = opt.instances;
  for (const Plane& p : r.planes)  // before any plane is encoded
    if (!container_holds(opt.container, p.texture.format))
      throw Error("profile " + profile.name + ": " + (opt.container == ContainerKind::DDS ? "DDS" : "KTX2") +
                  " cannot hold plane " + p.name + " (" + format_info(p.texture.format).name + ")");
  for (Plane& p : r.planes) {
    if (opt.plane_metadata) p.texture.metadata = plane_metadata(m, p.name);
    else p.texture.metadata.clear();
    std::vector<uint8_t> bytes = encode_container(opt.container, p.texture, opt.zstd);
    const std::string sha256 = sha256_hex(bytes.data(), bytes.size());  // once: the name and the manifest
    const std::string file =
        opt.stable_names ? opt.name + "." + p.name + "." + ext : plane_file_name_of_digest(opt.name, p.name, ext, sha256);
    out.files.push_back({file, std::move(bytes)});
    ManifestPlane mp;
    mp.name = p.name;
    mp.file = file;
    mp.format = p.texture.format;
    mp.width = p.texture.levels[0].width;
    mp.height = p.texture.levels[0].height;
    mp.levels = uint32_t(p.texture.levels.size());
    mp.layers = p.texture.layers;
    mp.bytes = out.files.back().bytes.size();
    mp.sha256 = sha256;
    m.planes.push_back(mp);
  }
  const std::string manifest_text = manifest_to_json(m);
  nlohmann::json report = convert_report_json(r, total_seconds);
  report["profile"] = profile.name;
  report["direction_fit"] = enum_name(kDirectionFits, fit.direction_fit);  // the fit that ran (a transcode: the stored one)
  for (auto it = opt.report_extra.begin(); it != opt.report_extra.end(); ++it) report[it.key()] = *it;
  const std::string report_text = report.dump(2) + "\n";
  // The manifest last: publishing it commits the set (files/output_set.h).
  out.files.push_back({opt.name + ".report.json", std::vector<uint8_t>(report_text.begin(), report_text.end())});
  out.files.push_back({opt.name + ".json", std::vector<uint8_t>(manifest_text.begin(), manifest_text.end())});
  return out;
}

}  // namespace ahd

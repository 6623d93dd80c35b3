// Packaging a conversion: its planes as container bytes, the manifest and the report, all in memory
// and named, ready for a caller to publish (files/output_set.h does it atomically on disk).
#pragma once
#include <ahd/convert.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/convert.h"
#include "pipeline/manifest.h"

namespace ahd {

struct PackageOptions {
  std::string name;  // the stem: NAME.<plane>.<ext>, NAME.json, NAME.report.json
  ContainerKind container = ContainerKind::KTX2;
  bool zstd = false;
  bool plane_metadata = true;  // ahd.* key/values in each plane (ConversionOptions::plane_metadata)
  bool stable_names = false;   // planes NAME.<plane>.<ext>, no content hash (ConversionOptions::stable_names)
  bool world_frame = false;    // the SH was world space + normals: d is in each texel's normal frame
  double iz_scale = 1.0;       // recorded: the SH was scaled by it before the fit (stored I_z = iz_scale × E)
  std::vector<ManifestInstance> instances;  // the scene's lightmapped instances (manifest "instances")
  nlohmann::json report_extra = nlohmann::json::object();  // merged into the report (e.g. "source")
};

struct PackagedConversion {
  Manifest manifest;
  std::vector<OutputFile> files;  // planes, then NAME.report.json, then NAME.json (last: it commits the set)
};

// Encodes every plane of `r` (attaching the plane metadata to r's textures) and assembles the
// manifest and the report. Throws ahd::Error on an invalid texture.
PackagedConversion package_conversion(PipelineResult& r, const Profile& profile, const FitOptions& fit,
                                      const PackageOptions& opt, double total_seconds);

// NAME.<plane>.<12 hex digits of the SHA-256 of bytes>.<ext>: a plane's file name in a set.
// Content-addressed, so a new set never overwrites a plane the previous manifest names
// (files/output_set.h publishes a set whole on that basis).
std::string plane_file_name(const std::string& name, const std::string& plane, const std::string& ext,
                            const std::vector<uint8_t>& bytes);

// The file extension of a container kind ("ktx2", "dds").
const char* container_extension(ContainerKind kind);

}  // namespace ahd

// Writing a conversion: plane containers, manifest and report, all encoded in memory first and
// then written through temporary names, so a failure leaves nothing half-written.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "containers/container.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"

namespace ahd::cli {

// OUT = DIR/NAME.EXT → planes DIR/NAME.<plane>.EXT, manifest DIR/NAME.json, report DIR/NAME.report.json.
struct OutputPaths {
  std::filesystem::path dir;
  std::string name;
  ContainerKind kind = ContainerKind::KTX2;
  std::string ext;
  std::string sibling(const std::string& suffix) const { return (dir / (name + suffix)).string(); }
};
OutputPaths output_paths(const std::string& out);

// Writes every plane, the manifest and the report (with `report_extra` merged in). Throws ahd::Error;
// on failure removes the files it already wrote.
Manifest write_conversion(const OutputPaths& out, ConvertResult& r, const Profile& profile, const FitOptions& fit,
                          bool world_frame, bool zstd, const nlohmann::json& report_extra, double total_seconds);

// The terminal summary of a conversion.
void print_conversion(const std::string& source, const OutputPaths& out, const Manifest& m, const ConvertResult& r,
                      bool closed_loop, size_t non_finite_inputs, double total_seconds);

}  // namespace ahd::cli

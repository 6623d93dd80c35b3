// The CLI's edges of a conversion: where OUT names the files, publishing the files the library
// returns, and the terminal summary.
#pragma once
#include <filesystem>
#include <string>

#include "pipeline/run.h"

namespace ahd::cli {

// OUT = DIR/NAME.EXT → planes DIR/NAME.<plane>.EXT, manifest DIR/NAME.json, report DIR/NAME.report.json.
struct OutputPaths {
  std::filesystem::path dir;
  std::string name;
  ContainerKind kind = ContainerKind::KTX2;
  std::string sibling(const std::string& suffix) const { return (dir / (name + suffix)).string(); }
};
// Throws ahd::Error("<out>: …") for an extension other than .ktx2/.dds.
OutputPaths output_paths(const std::string& out);

// Writes the files of a conversion into out.dir (the manifest last). Throws ahd::Error; on failure
// removes what it wrote.
void publish_conversion(const OutputPaths& out, const std::vector<OutputFile>& files);

// The terminal summary of a conversion.
void print_conversion(const std::string& source, const OutputPaths& out, const ConversionRun& run, bool closed_loop,
                      size_t non_finite_inputs);

}  // namespace ahd::cli

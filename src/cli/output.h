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

// Publishes the files of a conversion in out.dir as one set (io/output_set.h: temporaries, fsync,
// planes, then the manifest; the previous set's planes removed once the new manifest is in place).
// Throws ahd::Error naming the file; on failure the previous set stays intact.
void publish_conversion(const OutputPaths& out, std::vector<OutputFile> files);

// The terminal summary of a conversion.
void print_conversion(const std::string& source, const OutputPaths& out, const ConversionRun& run, bool closed_loop,
                      size_t non_finite_inputs);

}  // namespace ahd::cli

// The CLI's edges of a conversion: where OUT names the files, publishing the files the library
// returns, and the terminal summary.
#pragma once
#include <filesystem>
#include <optional>
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
// Throws ahd::Error("<out>: …") for an extension other than .ktx2/.dds, and for a NAME whose files
// `decode` would refuse (empty, hidden, or with '/', '\\' or ':': manifest.h is_plain_file_name),
// before anything is read or written.
OutputPaths output_paths(const std::string& out);

// What a publish does with NAME.ahd.exr (`convert --keep-intermediate`, read by `transcode`).
struct IntermediateFile {
  // The new intermediate, published with the set; none: the previous NAME.ahd.exr is removed with
  // the previous set (else `transcode` would re-emit an older conversion).
  std::optional<std::vector<uint8_t>> bytes;
  // Leave an existing NAME.ahd.exr alone (transcode from it into the same NAME: same fit).
  bool keep_existing = false;
};

// Publishes the files of a conversion (package.h: planes, NAME.report.json, NAME.json) in out.dir
// as one set (files/output_set.h's publish_output_set: the folder locked; temporaries, fsync; planes,
// then NAME.json as the commit, then the report and intermediate): each step's kill leaves a set
// whose every file belongs to its manifest. Removes once the new manifest is in place: the files
// the previous NAME.json names, and plane files of NAME that an interrupted run left unnamed
// (NAME.<plane>.<hash>.<ext> whose own SHA-256 begins with <hash>: written by ahdpack, so never a
// user's file). Throws ahd::Error naming the file; on failure the previous set stays intact.
void publish_conversion(const OutputPaths& out, std::vector<OutputFile> files, IntermediateFile intermediate = {});

// The terminal summary of a conversion.
void print_conversion(const std::string& source, const OutputPaths& out, const ConversionRun& run, bool closed_loop,
                      size_t non_finite_inputs);

// The conversion's warnings (bad or unsuitable data: pipeline/sh_input_check.h), one
// "ahdpack: warning: INPUT: …" line each on stderr; printed with --quiet too.
void print_warnings(const std::string& input, const PipelineResult& r);

}  // namespace ahd::cli

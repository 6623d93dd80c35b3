// Where OUT names a conversion's files, and publishing the files a conversion returns as one set:
// the cook's last step (cook/cook.h), and `transcode`'s.
#pragma once
#include <ahd/convert.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "files/utf8_path.h"

namespace ahd {

// OUT = DIR/NAME.EXT → planes DIR/NAME.<plane>.EXT, manifest DIR/NAME.json, report DIR/NAME.report.json.
struct OutputPaths {
  std::filesystem::path dir;
  std::string name;
  ContainerKind kind = ContainerKind::KTX2;
  std::string sibling(const std::string& suffix) const { return utf8_string(dir / fs_path(name + suffix)); }
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

}  // namespace ahd

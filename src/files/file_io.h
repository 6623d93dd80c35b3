// Whole files in: bounded reads of regular files, noted in the current input record
// (files/input_record.h), and the temporary names files/output_set.h publishes through.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

// A temporary name next to `path` (same file system): ".<name>.ahdtmp-<pid>-<random><ext>", the
// form files/output_set.h writes, recognises and removes when its process is gone.
std::string temp_path_for(const std::string& path);

// Reads a whole file once. Throws ahd::Error("<path>: <cause>"): missing, not a regular file (a
// device such as /dev/zero would never end), over max_bytes, or shorter than its size said.
std::vector<uint8_t> read_file_bytes(const std::string& path, size_t max_bytes = size_t(1) << 34);

// The bound on text inputs (profiles, placements, layouts, .import files): far above any real one.
constexpr size_t kMaxTextFileBytes = size_t(64) << 20;

// read_file_bytes for text inputs, bounded by kMaxTextFileBytes.
std::string read_text_file(const std::string& path, size_t max_bytes = kMaxTextFileBytes);

}  // namespace ahd

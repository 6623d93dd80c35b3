#include "files/file_io.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "core/error.h"
#include "files/input_file.h"
#include "files/input_record.h"

namespace ahd {
namespace fs = std::filesystem;

std::string temp_path_for(const std::string& path) {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  fs::path p(path);
  // ".<name>.ahdtmp-<pid>-<random><ext>": hidden, recognisable (remove_stale_temporaries in
  // files/output_set.h removes those whose process is gone), and ending in the final extension so
  // OpenImageIO picks the right writer.
  char tag[48];
  std::snprintf(tag, sizeof tag, ".ahdtmp-%ld-%08x", long(::getpid()), unsigned(rng()));
  return (p.parent_path() / ("." + p.filename().string() + tag + p.extension().string())).string();
}

std::vector<uint8_t> read_file_bytes(const std::string& path, size_t max_bytes) {
  return read_input_bytes(path, max_bytes);  // the one opener (files/input_file.h)
}

std::string read_text_file(const std::string& path, size_t max_bytes) {
  const std::vector<uint8_t> b = read_file_bytes(path, max_bytes);
  return std::string(b.begin(), b.end());
}

}  // namespace ahd

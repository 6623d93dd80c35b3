#include "files/file_io.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "core/error.h"
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
  std::error_code ec;
  if (!fs::exists(path, ec)) throw file_error(path, "file not found");
  // A device or pipe (/dev/zero) has no size to bound the read by: refused, not read forever.
  if (!fs::is_regular_file(path, ec)) throw file_error(path, "not a regular file");
  const auto size = fs::file_size(path, ec);
  if (ec) throw file_error(path, "cannot read size (" + ec.message() + ")");
  if (size > max_bytes)
    throw file_error(path, "file too large (" + std::to_string(size) + " bytes, at most " + std::to_string(max_bytes) + " are read)");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw file_error(path, "cannot open");
  note_input_file(path);
  std::vector<uint8_t> bytes(size);
  f.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size));
  if (!f) throw file_error(path, "read failed");
  return bytes;
}

std::string read_text_file(const std::string& path, size_t max_bytes) {
  const std::vector<uint8_t> b = read_file_bytes(path, max_bytes);
  return std::string(b.begin(), b.end());
}

}  // namespace ahd

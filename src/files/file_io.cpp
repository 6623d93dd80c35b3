#include "files/file_io.h"
#include "files/regular_file.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <cerrno>
#include <cstring>

#include "containers/sha256_stream.h"
#include "core/error.h"
#include "files/input_file.h"
#include "files/input_record.h"
#include "files/os_files.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

std::string temp_path_for(const std::string& path) {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  const fs::path p = fs_path(path);
  // ".<name>.ahdtmp-<pid>-<random><ext>": hidden, recognisable (remove_stale_temporaries in
  // files/output_set.h removes those whose process is gone), and ending in the final extension so
  // OpenImageIO picks the right writer.
  char tag[48];
  std::snprintf(tag, sizeof tag, ".ahdtmp-%ld-%08x", os::process_id(), unsigned(rng()));
  return utf8_string(p.parent_path() / fs_path("." + utf8_string(p.filename()) + tag + utf8_string(p.extension())));
}

std::vector<uint8_t> read_file_bytes(const std::string& path, size_t max_bytes) {
  return read_input_bytes(path, max_bytes);  // the one opener (files/input_file.h)
}

std::string read_text_file(const std::string& path, size_t max_bytes) {
  const std::vector<uint8_t> b = read_file_bytes(path, max_bytes);
  return std::string(b.begin(), b.end());
}

RegularFile::RegularFile(const std::string& path, uint64_t max_bytes, bool no_symlink)
    : path_(path), file_(std::make_unique<os::ReadFile>()) {
  // Opened without blocking and without following a symlink when asked (files/os_files.h).
  if (const int e = os::open_for_reading(path, no_symlink, file_.get()))
    throw file_error(path, e == ENOENT ? "file not found" : "cannot open (" + os::error_text(e) + ")");
  bool regular = false;
  if (os::file_status(*file_, &regular, &size_) != 0 || !regular) throw file_error(path, "not a regular file");
  if (size_ > max_bytes)
    throw file_error(path, "file too large (" + std::to_string(size_) + " bytes, at most " + std::to_string(max_bytes) +
                               " are read)");
}

RegularFile::~RegularFile() = default;

void RegularFile::read(uint8_t* out, size_t n) {
  while (n > 0) {
    const long got = os::read_some(*file_, out, std::min(n, size_t(1) << 30));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw file_error(path_, "read failed (" + std::string(std::strerror(errno)) + ")");
    if (got == 0) throw file_error(path_, "read failed (shorter than its size)");
    out += got, n -= size_t(got);
  }
}

std::string file_sha256(const std::string& path, uint64_t max_bytes, uint64_t* size, bool no_symlink) {
  RegularFile f(path, max_bytes, no_symlink);
  std::vector<uint8_t> buf(size_t(1) << 20);
  Sha256 h;
  for (uint64_t left = f.size(); left > 0;) {
    const size_t n = size_t(std::min<uint64_t>(left, buf.size()));
    f.read(buf.data(), n);
    h.update(buf.data(), n);
    left -= n;
  }
  if (size) *size = f.size();
  return h.hex();
}

}  // namespace ahd

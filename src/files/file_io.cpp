#include "files/file_io.h"
#include "files/regular_file.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "containers/sha256_stream.h"
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

RegularFile::RegularFile(const std::string& path, uint64_t max_bytes, bool no_symlink) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | (no_symlink ? O_NOFOLLOW : 0));
  if (fd_ < 0) throw file_error(path, errno == ENOENT ? "file not found" : "cannot open (" + std::string(std::strerror(errno)) + ")");
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw file_error(path, "not a regular file");
  }
  size_ = uint64_t(st.st_size);
  if (size_ > max_bytes) {
    ::close(fd_);
    throw file_error(path, "file too large (" + std::to_string(size_) + " bytes, at most " + std::to_string(max_bytes) +
                               " are read)");
  }
  // Back to blocking reads (a regular file never blocks on O_NONBLOCK anyway).
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
}

RegularFile::~RegularFile() {
  if (fd_ >= 0) ::close(fd_);
}

void RegularFile::read(uint8_t* out, size_t n) {
  while (n > 0) {
    const ssize_t got = ::read(fd_, out, std::min(n, size_t(1) << 30));
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

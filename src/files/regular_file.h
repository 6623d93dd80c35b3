// Regular files read in pieces: opened without blocking, checked by fstat, bounded (the cache's
// entries and records, the key's hashing of inputs, the clean-up's hashing of old planes).
#pragma once
#include <cstdint>
#include <memory>
#include <string>

namespace ahd {
namespace os {
struct ReadFile;  // files/os_files.h
}

// A regular file opened for reading, for streamed reads: opened with O_NONBLOCK (a FIFO opens
// without waiting for a writer) and O_NOFOLLOW when `no_symlink`, then checked with fstat on the
// descriptor itself (no check-then-open race): a device, FIFO, socket or folder is refused, and a
// file over max_bytes (its size from fstat: a sparse file's full length). Not noted in the input
// record. Throws ahd::Error("<path>: <cause>"). Closes on destruction; not copyable.
class RegularFile {
 public:
  RegularFile(const std::string& path, uint64_t max_bytes, bool no_symlink = false);
  ~RegularFile();
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;
  uint64_t size() const { return size_; }
  // Reads exactly n bytes (retrying short reads); throws naming the file when it ends first.
  void read(uint8_t* out, size_t n);

 private:
  std::string path_;
  std::unique_ptr<os::ReadFile> file_;
  uint64_t size_ = 0;
};

// SHA-256 (hex) of a regular file of at most max_bytes (RegularFile's checks), read through a
// 1 MiB buffer, never held whole. *size receives its byte count. Throws ahd::Error naming it.
std::string file_sha256(const std::string& path, uint64_t max_bytes, uint64_t* size, bool no_symlink = false);

}  // namespace ahd

#include "files/input_file.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>

#include "core/error.h"
#include "core/large_buffer.h"
#include "files/input_record.h"
#include "files/os_files.h"

namespace ahd {

size_t input_file_bound(InputKind kind) {
  switch (kind) {
    case InputKind::kImage: return size_t(1) << 34;        // 16 GiB: a 16k × 16k float RGBA EXR is 4 GiB
    case InputKind::kText: return size_t(64) << 20;        // 64 MiB
    case InputKind::kSceneText: return size_t(64) << 20;   // 64 MiB: a large level's .tscn is a few MB
    case InputKind::kLmbake: return size_t(64) << 20;      // 64 MiB: 40 bytes and a path per user
    case InputKind::kUnwrapCache: return size_t(1) << 30;  // 1 GiB: 16 bytes per vertex and 4 per index
    case InputKind::kMesh: return size_t(1) << 31;         // 2 GiB
  }
  return size_t(64) << 20;
}

namespace {

std::string errno_text(int e) { return os::error_text(e); }

}  // namespace

std::vector<uint8_t> read_input_bytes(const std::string& path, size_t max_bytes) {
  return read_input_head(path, max_bytes, SIZE_MAX, nullptr);
}

std::vector<uint8_t> read_input_head(const std::string& path, size_t max_bytes, size_t head_bytes,
                                     uint64_t* file_bytes) {
  bool regular = false;
  uint64_t size = 0;
  if (const int e = os::path_status(path, &regular, &size)) {
    if (e == ENOENT || e == ENOTDIR) throw file_error(path, "file not found");
    throw file_error(path, "cannot open (" + errno_text(e) + ")");
  }
  // A device or pipe (/dev/zero, a FIFO) has no size to bound the read by: refused, not read forever.
  if (!regular) throw file_error(path, "not a regular file");
  // Opened without blocking: a FIFO put in the file's place after the stat would block this open for ever.
  os::ReadFile f;
  if (const int e = os::open_for_reading(path, false, &f)) {
    if (e == ENOENT) throw file_error(path, "file not found");
    throw file_error(path, "cannot open (" + errno_text(e) + ")");
  }
  if (os::file_status(f, &regular, &size) != 0 || !regular) throw file_error(path, "not a regular file");
  if (size > max_bytes)
    throw file_error(path, "file too large (" + std::to_string(size) + " bytes, at most " + std::to_string(max_bytes) +
                               " are read)");
  if (file_bytes) *file_bytes = size;
  // Advised for huge pages: a 1024² L1 canonical EXR is 42 MB, 10 000 page faults in 4 KB pages.
  std::vector<uint8_t> bytes;
  assign_large(bytes, static_cast<size_t>(std::min<uint64_t>(size, head_bytes)), uint8_t(0));
  size_t got = 0;
  while (got < bytes.size()) {
    const long n = os::read_some(f, bytes.data() + got, bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw file_error(path, "read failed (" + errno_text(errno) + ")");
    if (n == 0) throw file_error(path, "read failed (shorter than its size said: changed while read)");
    got += size_t(n);
  }
  note_input_file(path);
  return bytes;
}

bool input_exists(const std::string& path) {
  bool regular = false;
  uint64_t size = 0;
  const int e = os::path_status(path, &regular, &size);
  const bool found = e == 0;
  if (e == ELOOP) throw file_error(path, "symbolic links loop (" + errno_text(ELOOP) + ")");
  // Noted as a probe: what a reader reads depends on it, so the cache's direct lookup checks it
  // again (an .import or unwrap cache that appears later reads the input again, no stale hit).
  (void)probe_input_file(path);
  return found;
}

std::string read_input_text(const std::string& path, InputKind kind) {
  const std::vector<uint8_t> b = read_input_bytes(path, kind);
  return std::string(b.begin(), b.end());
}

}  // namespace ahd

// Little-endian byte writing/reading with bounds checks, shared by the container codecs.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"

namespace ahd::bytes {

inline void put32(std::vector<uint8_t>& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(uint8_t(v >> (8 * i)));
}
inline void put64(std::vector<uint8_t>& b, uint64_t v) {
  for (int i = 0; i < 8; ++i) b.push_back(uint8_t(v >> (8 * i)));
}
inline void set32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = uint8_t(v >> (8 * i));
}
inline void set64(std::vector<uint8_t>& b, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) b[at + i] = uint8_t(v >> (8 * i));
}
inline void pad_to(std::vector<uint8_t>& b, size_t align) {
  while (b.size() % align) b.push_back(0);
}

// A bounds-checked view of untrusted bytes: every read names the file in its error.
class Reader {
 public:
  Reader(const uint8_t* data, size_t size, const std::string& path) : d_(data), n_(size), path_(path) {}
  size_t size() const { return n_; }
  void need(uint64_t offset, uint64_t length, const char* what) const {
    if (offset > n_ || length > n_ - offset) throw file_error(path_, std::string("truncated or out-of-bounds ") + what);
  }
  uint32_t u32(uint64_t at) const {
    need(at, 4, "field");
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(d_[at + i]) << (8 * i);
    return v;
  }
  uint64_t u64(uint64_t at) const { return uint64_t(u32(at)) | uint64_t(u32(at + 4)) << 32; }
  const uint8_t* at(uint64_t offset, uint64_t length, const char* what) const {
    need(offset, length, what);
    return d_ + offset;
  }
  [[noreturn]] void fail(const std::string& cause) const { throw file_error(path_, cause); }

 private:
  const uint8_t* d_;
  size_t n_;
  std::string path_;
};

}  // namespace ahd::bytes

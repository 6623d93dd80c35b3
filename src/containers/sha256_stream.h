// SHA-256 fed in pieces (containers/sha256.h computes the same digest of one buffer).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace ahd {

// The same digest fed in pieces (a file hashed through one reused buffer, never held whole):
// update() any number of times, then hex() once. Same digest as sha256_hex of the concatenation.
class Sha256 {
 public:
  void update(const uint8_t* data, size_t size);
  std::string hex();

 private:
  uint32_t h_[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  uint8_t buf_[64] = {};
  size_t buffered_ = 0;
  uint64_t total_ = 0;
};

}  // namespace ahd

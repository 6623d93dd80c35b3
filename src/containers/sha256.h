// SHA-256 (FIPS 180-4), written from the standard: the content hash the manifest records for each
// plane file, so a set mixed by an interrupted write (or edited by hand) is detected before decoding.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace ahd {

// Lower-case hex digest (64 characters) of `size` bytes.
std::string sha256_hex(const uint8_t* data, size_t size);

}  // namespace ahd

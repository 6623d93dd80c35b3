// SHA-256 (FIPS 180-4), written from the standard: the content hash the manifest records for each
// plane file, so a set mixed by an interrupted write (or edited by hand) is detected before decoding.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace ahd {

// Which block function computes the digest: the CPU's SHA extensions (x86 SHA-NI) when it has
// them — about 6× faster; a 2048² plain lightmap's chain is 5.6 MB hashed on the critical path —
// or the portable one. Both give the same digest (test ContainerTest.Sha256PathsAgree).
enum class Sha256Path { Best, Portable };

// True when Sha256Path::Best uses the CPU's SHA extensions.
bool sha256_hardware();

// Lower-case hex digest (64 characters) of `size` bytes.
std::string sha256_hex(const uint8_t* data, size_t size, Sha256Path path = Sha256Path::Best);

}  // namespace ahd

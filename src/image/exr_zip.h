// OpenEXR's ZIP and ZIPS chunks decoded with libdeflate (issue 45: zlib's inflate was most of the
// read of a canonical SH EXR, and the read a fifth of a small L1/L2 conversion). Internal to
// src/image: exr_read.cpp decodes a band's chunks with it and leaves every other chunk, and any
// chunk this refuses, to OpenEXR — so the values are OpenEXR's, bit for bit, and so is every error.
#pragma once
#include <cstddef>
#include <cstdint>

namespace ahd {

// True when this build has libdeflate and the path is on (the tests switch it off to compare the
// two paths; it is on by default).
bool exr_zip_available();
void set_exr_zip_enabled(bool on);

// One chunk's stored bytes (`raw`, `n` of them) to the bytes of its lines (`out`, `size`), as
// OpenEXR's ZIP compressor defines them: stored as they are when not smaller than the lines;
// otherwise a zlib stream of the lines' bytes, delta-coded byte after byte and split into their
// even and odd halves. False (out unspecified) when the stream is not a zlib stream of exactly
// `size` bytes or libdeflate is missing. Thread safe (a decompressor per thread).
bool exr_unzip_chunk(const uint8_t* raw, size_t n, uint8_t* out, size_t size);

// The step after inflating: `t` (`size` inflated bytes, overwritten) to the lines' bytes `out` —
// the predictor undone, the two halves interleaved. SSE2 and plain loops, the same bytes.
void exr_zip_unpack(uint8_t* t, uint8_t* out, size_t size);

}  // namespace ahd

// KTX 2.0 (Khronos) writer and reader for the formats in core/pixel_format.h: 2D or 2D array (layerCount), one
// face, a full or partial mip chain, complete basic Data Format Descriptor, sorted key/value data,
// optional Zstandard supercompression (scheme 2).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/texture.h"

namespace ahd {

struct Ktx2WriteOptions {
  bool zstd = false;
  int zstd_level = 9;  // deterministic for a given libzstd version
};

// Writes KTXwriter and KTXorientation ("rd") plus tex.metadata. Throws ahd::Error.
std::vector<uint8_t> write_ktx2(const Texture& tex, const Ktx2WriteOptions& opt = {});

// Safe on untrusted input. Returns levels largest first and every key/value pair.
Texture read_ktx2(const uint8_t* data, size_t size, const std::string& path_for_errors);

// The basic DFD (including its leading total-size word) the writer emits for a format.
std::vector<uint32_t> ktx2_dfd(PixelFormat f);

}  // namespace ahd

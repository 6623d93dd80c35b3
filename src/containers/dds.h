// DDS writer and reader (DX10 extended header) for the formats in core/pixel_format.h:
// 2D or 2D array (DX10 arraySize; arrays always take the DX10 header), full or partial mip chain. DDS has no key/value store: metadata is not written
// (the JSON manifest carries it) and read_dds returns none.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/texture.h"

namespace ahd {

// Like DirectXTex, writes a legacy header where one describes the format exactly (BC4 "BC4U",
// BC5 "BC5U", RGBA8 as 32-bit masks) and the DX10 extension otherwise. Throws ahd::Error on an
// invalid texture.
std::vector<uint8_t> write_dds(const Texture& tex);

// Safe on untrusted input: header fields are validated before any allocation. Accepts DX10 files
// of our formats, the legacy FourCC ATI1/BC4U (BC4) and ATI2/BC5U (BC5), and 32-bit RGBA masks.
Texture read_dds(const uint8_t* data, size_t size, const std::string& path_for_errors);

}  // namespace ahd

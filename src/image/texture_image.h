// A KTX2 or DDS texture read as an image (level 0): engines ship their lightmaps so (Bevy: one
// B10G11R11 KTX2 per object, zstd-supercompressed). Every format the containers read (core/
// pixel_format_table.h) decodes to floats through its codec.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"
#include "image/image_io.h"

namespace ahd {

// True when `bytes` start with the KTX2 or DDS magic.
bool is_texture_container_bytes(const std::vector<uint8_t>& bytes);

// The header of read_texture_image's image, without decoding the pixels (the container is parsed).
ImageFileInfo read_texture_info(const std::string& path, const std::vector<uint8_t>& bytes, int part);

// Level 0 of the texture in `bytes` as floats, the format's channels (R, G, B[, A]; R or RG for
// one- and two-channel formats), rows top first as stored. *info (optional): size, channel names,
// is_float from the format. Throws ahd::Error("<path>: <cause>") on a malformed or unsupported
// file, and for an array texture of several layers or a part other than 0 (one lightmap per
// file). Safe on untrusted input (the container readers validate before allocating).
ImageF read_texture_image(const std::string& path, const std::vector<uint8_t>& bytes, int part, ImageFileInfo* info);

}  // namespace ahd

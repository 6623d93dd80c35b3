// Containers: one Texture ↔ the bytes of a KTX2 or DDS file (bytes only: files are files/container_file.h).
#pragma once
#include <ahd/types.h>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/texture.h"

namespace ahd {


// By extension (.ktx2 / .dds, any case). Throws ahd::Error("<path>: …") for anything else.
ContainerKind container_kind_from_path(const std::string& path);

// True when the container can hold the format (its row's ContainerBits, codecs/pixel_format_table.h).
bool container_holds(ContainerKind kind, PixelFormat f);

// Serialises `tex` (levels[0] = full size; each level must hold exactly level_size_bytes()).
// `zstd` supercompresses KTX2 levels (ignored for DDS). Throws ahd::Error on an invalid texture.
std::vector<uint8_t> encode_container(ContainerKind kind, const Texture& tex, bool zstd = false);

// Parses untrusted bytes; every field is validated before any allocation. Throws
// ahd::Error("<path_for_errors>: <cause>") on anything malformed, truncated or unsupported.
Texture decode_container(ContainerKind kind, const uint8_t* data, size_t size, const std::string& path_for_errors);

// Detects the container by its magic bytes and parses it (as decode_container). Throws
// ahd::Error("<path_for_errors>: neither a KTX2 nor a DDS file") for anything else.
Texture decode_container_auto(const uint8_t* data, size_t size, const std::string& path_for_errors);

}  // namespace ahd

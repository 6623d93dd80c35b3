// KTX2/DDS files on disk: the file-system edge of containers/container.h.
#pragma once
#include <string>

#include "containers/container.h"

namespace ahd {

// Reads a file and detects the container by its magic bytes. Throws ahd::Error("<path>: <cause>").
Texture read_container_file(const std::string& path);

// Encodes (container by extension) and writes atomically (temporary name + rename).
void write_container_file(const std::string& path, const Texture& tex, bool zstd = false);

}  // namespace ahd

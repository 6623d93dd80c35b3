#include "files/container_file.h"

#include <cstdint>

#include "containers/limits.h"
#include "files/file_io.h"
#include "files/output_set.h"

namespace ahd {

// The largest container the size limit allows: every level of a full mip chain (4/3 of level 0,
// layers within the same texel budget) at 16 bytes a texel (RGBA32F, the widest format), plus
// 16 MiB of metadata. A larger file is refused before it is read (issue 26: `inspect` read a whole
// 8 GiB file into memory first).
size_t max_container_bytes() {
  const uint64_t lim = max_image_size();
  if (lim > (uint64_t(1) << 24)) return SIZE_MAX;  // the product below would overflow
  return size_t(lim * lim / 3 * 4 * 16 + (uint64_t(16) << 20));
}

Texture read_container_file(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path, max_container_bytes());
  return decode_container_auto(bytes.data(), bytes.size(), path);
}

void write_container_file(const std::string& path, const Texture& tex, bool zstd) {
  write_file_atomic(path, encode_container(container_kind_from_path(path), tex, zstd));
}

}  // namespace ahd

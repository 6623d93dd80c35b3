#include "io/container_file.h"

#include "io/image_io.h"

namespace ahd {

Texture read_container_file(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  return decode_container_auto(bytes.data(), bytes.size(), path);
}

void write_container_file(const std::string& path, const Texture& tex, bool zstd) {
  write_file_atomic(path, encode_container(container_kind_from_path(path), tex, zstd));
}

}  // namespace ahd

#include "containers/container.h"

#include <algorithm>
#include <filesystem>
#include <new>

#include "containers/dds.h"
#include "containers/ktx2.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"

namespace ahd {

ContainerKind container_kind_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".ktx2") return ContainerKind::KTX2;
  if (ext == ".dds") return ContainerKind::DDS;
  throw file_error(path, "unknown container extension (use .ktx2 or .dds)");
}

bool container_holds(ContainerKind kind, PixelFormat f) {
  return pixel_format_row(f).containers & (kind == ContainerKind::DDS ? kInDds : kInKtx2);
}

std::vector<uint8_t> encode_container(ContainerKind kind, const Texture& tex, bool zstd) {
  if (kind == ContainerKind::DDS) return write_dds(tex);
  Ktx2WriteOptions o;
  o.zstd = zstd;
  return write_ktx2(tex, o);
}

Texture decode_container(ContainerKind kind, const uint8_t* data, size_t size, const std::string& path) {
  return kind == ContainerKind::DDS ? read_dds(data, size, path) : read_ktx2(data, size, path);
}

Texture decode_container_auto(const uint8_t* data, size_t size, const std::string& path) {
  const bool ktx = size >= 4 && data[0] == 0xAB && data[1] == 'K' && data[2] == 'T' && data[3] == 'X';
  const bool dds = size >= 4 && data[0] == 'D' && data[1] == 'D' && data[2] == 'S' && data[3] == ' ';
  if (!ktx && !dds) throw file_error(path, "neither a KTX2 nor a DDS file");
  try {
    return decode_container(ktx ? ContainerKind::KTX2 : ContainerKind::DDS, data, size, path);
  } catch (const std::bad_alloc&) {
    // Sizes were validated against the limit before allocating; the machine is short of memory.
    throw file_error(path, "out of memory decoding the file");
  }
}

}  // namespace ahd

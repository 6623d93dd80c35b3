#include "files/manifest_file.h"

#include <filesystem>

#include "containers/container.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "files/file_io.h"
#include "files/utf8_path.h"

namespace ahd {

Manifest read_manifest_file(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path, size_t(1) << 24);
  return manifest_from_json(std::string(bytes.begin(), bytes.end()), path);
}

Texture read_manifest_plane(const std::string& manifest_path, const ManifestPlane& p) {
  const std::string path = utf8_string(fs_path(manifest_path).parent_path() / fs_path(p.file));
  std::error_code ec;
  const auto size = std::filesystem::file_size(fs_path(path), ec);
  if (ec) throw file_error(path, "missing plane file of " + manifest_path);
  // The size first: a foreign or truncated file is refused without reading it.
  if (size != p.bytes)
    throw file_error(path, "does not match the manifest (" + std::to_string(size) + " bytes, the manifest says " +
                               std::to_string(p.bytes) + "; an interrupted or mixed output set?)");
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  if (sha256_hex(bytes.data(), bytes.size()) != p.sha256)
    throw file_error(path, "does not match the manifest (content hash differs; an interrupted or mixed output set?)");
  Texture t = decode_container(container_kind_from_path(path), bytes.data(), bytes.size(), path);
  if (t.format != p.format)
    throw file_error(path, std::string("holds ") + format_info(t.format).name + " but the manifest says " +
                               format_info(p.format).name);
  if (t.levels[0].width != p.width || t.levels[0].height != p.height || t.levels.size() != p.levels)
    throw file_error(path, "size or level count differs from the manifest");
  return t;
}

}  // namespace ahd

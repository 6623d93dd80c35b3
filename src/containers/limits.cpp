#include "containers/limits.h"

#include <algorithm>
#include <atomic>
#include <cctype>

#include "core/error.h"

namespace ahd {
namespace {

std::atomic<uint32_t> g_override{0};

}  // namespace

uint32_t max_image_size() {
  const uint32_t o = g_override.load(std::memory_order_relaxed);
  return o ? o : kDefaultMaxImageSize;
}

void set_max_image_size(uint32_t size) { g_override.store(size, std::memory_order_relaxed); }

void check_image_size(const std::string& path, uint64_t width, uint64_t height) {
  if (width == 0 || height == 0)
    throw file_error(path, "empty image (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  const uint32_t lim = max_image_size();
  if (width > lim || height > lim)
    throw file_error(path, std::to_string(width) + "x" + std::to_string(height) + " is over the size limit of " +
                               std::to_string(lim) + "x" + std::to_string(lim) +
                               " texels per level (AHDPACK_MAX_SIZE raises it)");
}

}  // namespace ahd

namespace ahd {

void check_layered_size(const std::string& path, uint64_t width, uint64_t height, uint64_t layers) {
  check_image_size(path, width, height);
  const uint64_t lim = max_image_size();
  if (layers == 0 || width * height * layers > lim * lim)
    throw file_error(path, std::to_string(layers) + " layers of " + std::to_string(width) + "x" + std::to_string(height) +
                               " are over the size limit of " + std::to_string(lim) + "x" + std::to_string(lim) +
                               " texels per level, all layers together (AHDPACK_MAX_SIZE raises it)");
}

}  // namespace ahd

namespace ahd {

uint64_t max_expansion(const std::string& codec_in) {
  std::string codec = codec_in.substr(0, codec_in.find(':'));  // "dwaa:45" → "dwaa"
  for (char& c : codec) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (codec == "none" || codec == "uncompressed") return 2;
  if (codec == "rle" || codec == "targa-rle" || codec == "hdr-rle") return 160;
  if (codec == "b44" || codec == "b44a") return 16;
  if (codec == "piz") return 600;
  if (codec == "dwaa" || codec == "dwab") return 64 * 1100;
  return 1100;  // zip, zips, pxr24, png (deflate), anything else
}

uint64_t checked_mul(const std::string& path, const std::string& what, uint64_t a, uint64_t b, uint64_t limit) {
  if (a != 0 && b > limit / a) throw file_error(path, what + " overflows (" + std::to_string(a) + " x " + std::to_string(b) + ")");
  return a * b;
}

void check_declared_image(const std::string& path, uint64_t width, uint64_t height, uint64_t layers,
                          uint64_t bytes_per_texel, uint64_t file_bytes, const std::string& codec) {
  check_layered_size(path, width, height, layers);
  // width and height are below 2^32 here, so their product fits; the rest is checked.
  const uint64_t texels = checked_mul(path, "declared image size", width * height, layers);
  const uint64_t declared = checked_mul(path, "declared image size", texels, std::max<uint64_t>(1, bytes_per_texel));
  const uint64_t ratio = max_expansion(codec);
  const uint64_t plausible = file_bytes > (UINT64_MAX - 65536) / ratio ? UINT64_MAX : file_bytes * ratio + 65536;
  if (declared > plausible)
    throw file_error(path, "the header claims " + std::to_string(width) + "x" + std::to_string(height) +
                               (layers > 1 ? "x" + std::to_string(layers) : std::string()) + " texels (" +
                               std::to_string(declared) + " bytes of samples) but the file has only " +
                               std::to_string(file_bytes) + " bytes (" + (codec.empty() ? "unknown" : codec) +
                               " data expands at most " + std::to_string(ratio) + "x): truncated or forged");
}

}  // namespace ahd

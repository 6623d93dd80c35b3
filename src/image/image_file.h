// An image file read once into memory and decoded from there (OpenImageIO through a memory
// proxy, in the module of image/oiio_module.h): a file replaced or truncated while it is read
// changes nothing we parse, so the header that sized a buffer is the header of the pixels written
// into it. Internal to src/image.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "image/oiio_module.h"

namespace ahd {

// An open OpenImageIO input over the file's bytes. Move-only; closes its handle when destroyed.
struct OpenedImage {
  std::string path;
  std::vector<uint8_t> bytes;  // the whole file, read once
  const OiioModule* oiio = nullptr;
  void* handle = nullptr;
  OiioSpec spec;  // the header of the part/mip last sought (part 0, mip 0 after opening)

  OpenedImage() = default;
  OpenedImage(OpenedImage&& o) noexcept;
  OpenedImage& operator=(OpenedImage&&) = delete;
  ~OpenedImage();

  // Positions on part/mip and sets `spec`; false when there is none.
  bool seek(int part, int mip);
};

// Reads `path` once (regular files only, bounded by read_file_bytes) and opens it from memory.
// `unassociated_alpha`: keep colours as stored instead of OpenImageIO's alpha association. Throws
// ahd::Error("<path>: <cause>"): missing, not an image (OpenImageIO's first message line), no
// OpenImageIO module.
OpenedImage open_image_file(const std::string& path, bool unassociated_alpha = false);

// open_image_file over bytes the caller has already read from `path`.
OpenedImage open_image_bytes(const std::string& path, std::vector<uint8_t> bytes, bool unassociated_alpha);

// The plausibility check of the current part's header (`spec`) before its pixels are allocated:
// not deep, not a volume, check_declared_image against the file's size and codec with `layers`
// images of spec's size (a mip chain: pass 1 for level 0; later levels are smaller). Throws.
void check_image_spec(const OpenedImage& f, const OiioSpec& spec, uint64_t layers = 1);

}  // namespace ahd

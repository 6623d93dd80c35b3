// An image file read once into memory and decoded from there (OpenImageIO through a memory
// proxy): a file replaced or truncated while it is read changes nothing we parse, so the header
// that sized a buffer is the header of the pixels written into it. Internal to src/io.
#pragma once
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ahd {

struct OpenedImage {
  std::string path;
  std::vector<uint8_t> bytes;  // the whole file, read once
  std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
  std::unique_ptr<OIIO::ImageInput> in;
};

// Reads `path` once (regular files only, bounded by read_file_bytes) and opens it from memory.
// `config`: OpenImageIO open hints (may be null). Throws ahd::Error("<path>: <cause>"): missing,
// not an image (OpenImageIO's first message line).
OpenedImage open_image_file(const std::string& path, const OIIO::ImageSpec* config = nullptr);

// The plausibility check of the current part's header (`spec`) before its pixels are allocated:
// not deep, not a volume, check_declared_image against the file's size and codec with `layers`
// images of spec's size (a mip chain: pass 1 for level 0; later levels are smaller). Throws.
void check_image_spec(const OpenedImage& f, const OIIO::ImageSpec& spec, uint64_t layers = 1);

}  // namespace ahd

// Image readers through OpenImageIO as ahdpack calls them (header check, then pixels): byte 0
// picks the extension (.png / .tga / .hdr / .exr), the rest is the file. Seeds: small images of
// each kind written by scripts/fuzz.sh. A header claiming more than the file holds must be an
// ahd::Error before anything is allocated (-malloc_limit_mb catches a bomb).
#include "fuzz_common.h"
#include "image/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExt[4] = {".png", ".tga", ".hdr", ".exr"};
  const std::string path = ahd_fuzz::write_temp(data + 1, size - 1, kExt[data[0] & 3]);
  ahd_fuzz::expect_clean([&] {
    ahd::ImageFileInfo info;
    const ahd::ImageF img = ahd::read_image(path, &info);
    if (img.width != info.width || img.height != info.height) __builtin_trap();
  });
  return 0;
}

// A KTX2 or DDS lightmap read as an input image (read_texture_image: Bevy's zstd-supercompressed
// B10G11R11 KTX2, any format the containers read, decoded to floats; issue 44). The header path
// (read_texture_info) and the decode must agree on the size. Seeds: the golden planes (KTX2, DDS)
// and a zstd-supercompressed plane from scripts/fuzz.sh.
#include "fuzz_common.h"
#include "image/texture_image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> bytes(data, data + size);
  if (!ahd::is_texture_container_bytes(bytes)) return 0;
  ahd_fuzz::expect_clean([&] {
    const ahd::ImageFileInfo head = ahd::read_texture_info("f.ktx2", bytes, 0);
    ahd::ImageFileInfo info;
    const ahd::ImageF img = ahd::read_texture_image("f.ktx2", bytes, 0, &info);
    if (img.width != info.width || img.height != info.height || head.width != info.width || head.height != info.height)
      __builtin_trap();
    if (img.data.size() != size_t(img.width) * size_t(img.height) * size_t(img.channels)) __builtin_trap();
  });
  return 0;
}

// The intermediate EXR reader (seeds: NAME.ahd.exr of the golden inputs, made by scripts/fuzz.sh).
// The EXR parsing itself is OpenEXR's (not instrumented); this exercises our checks after it.
#include "fuzz_common.h"
#include "image/ahd_intermediate.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ahd_fuzz::write_temp(data, size, ".ahd.exr");
  ahd::FitOptions fit;
  ahd_fuzz::expect_clean([&] { ahd::read_intermediate(path, &fit); });
  return 0;
}

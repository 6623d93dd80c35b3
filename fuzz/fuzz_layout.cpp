// Baker layout JSON (seeds: formats/bakers/*.json).
#include "fuzz_common.h"
#include "bakers/baker_layout.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ahd_fuzz::write_temp(data, size, ".json");
  ahd_fuzz::expect_clean([&] { ahd::load_layout(path); });
  return 0;
}

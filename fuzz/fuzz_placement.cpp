// Placement files (read_placements): Unity scene YAML (text starting "%YAML") or the JSON form.
// Seeds: a minimal Unity scene and a JSON placement from scripts/fuzz.sh.
#include "fuzz_common.h"
#include "scene/placement_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ahd_fuzz::write_temp(data, size, ".unity");
  ahd_fuzz::expect_clean([&] { ahd::read_placements(path); });
  return 0;
}

// DDS reader on untrusted bytes (seeds: golden/expected/*.dds).
#include "containers/dds.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ahd_fuzz::expect_clean([&] { ahd::read_dds(data, size, "fuzz.dds"); });
  return 0;
}

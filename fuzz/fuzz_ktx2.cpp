// KTX2 reader on untrusted bytes (seeds: golden/expected/*.ktx2).
#include "containers/ktx2.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ahd_fuzz::expect_clean([&] { ahd::read_ktx2(data, size, "fuzz.ktx2"); });
  return 0;
}

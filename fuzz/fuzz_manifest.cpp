// Manifest parser and validator (seeds: golden/expected/*.json manifests). What it accepts must
// also be safe to hand to the plane-role checks the decoder relies on.
#include <string>

#include "fuzz_common.h"
#include "pipeline/manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ahd_fuzz::expect_clean([&] {
    const ahd::Manifest m = ahd::manifest_from_json(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    for (const auto& p : m.planes)
      if (!ahd::plane_format_problem(p.name, p.format, m.ratio_form).empty()) __builtin_trap();  // accepted a misfit
    (void)ahd::manifest_to_json(m);
  });
  return 0;
}

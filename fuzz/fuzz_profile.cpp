// Output profiles (profile_from_json, as --profile FILE.json reads them). Seeds:
// formats/profiles/*.json. A profile that parses must be one decode accepts: every plane's format
// passes plane_format_problem (checked again here, so a validator gap traps).
#include "fuzz_common.h"
#include "pipeline/manifest.h"
#include "pipeline/profile.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ahd_fuzz::expect_clean([&] {
    const ahd::Profile p = ahd::profile_from_json(text, "fuzz.json");
    const ahd::RatioForm form = p.ratio_rgb ? ahd::RatioForm::Rgb : ahd::RatioForm::Luminance;
    if (!ahd::plane_format_problem("iz", p.iz, form).empty()) __builtin_trap();
    if (p.packed_dir_ratio ? !ahd::plane_format_problem("dirratio", p.dirratio, form).empty()
                           : !ahd::plane_format_problem("dir", p.dir, form).empty() ||
                                 !ahd::plane_format_problem("ratio", p.ratio, form).empty())
      __builtin_trap();
  });
  return 0;
}

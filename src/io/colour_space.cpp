#include "io/colour_space.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace ahd {

void check_working_space(const ImageFileInfo& info, const std::string& path) {
  if (!info.is_float) return;
  static const float rec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  if (info.chromaticities.size() == 8)
    for (int i = 0; i < 8; ++i)
      if (!(std::fabs(info.chromaticities[size_t(i)] - rec709[i]) <= 1e-3f)) {
        char b[200];
        std::snprintf(b, sizeof b, "declares chromaticities R(%.4g, %.4g) G(%.4g, %.4g) B(%.4g, %.4g) W(%.4g, %.4g)",
                      info.chromaticities[0], info.chromaticities[1], info.chromaticities[2], info.chromaticities[3],
                      info.chromaticities[4], info.chromaticities[5], info.chromaticities[6], info.chromaticities[7]);
        throw file_error(path, std::string(b) + ", not the working space " + kWorkingSpace +
                                   ": convert it first (no OpenColorIO conversion is built in)");
      }
  std::string cs = info.color_space;
  std::transform(cs.begin(), cs.end(), cs.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  const bool linear = cs.empty() || cs == "linear" || cs == "lin_srgb" || cs == "lin_rec709" || cs == "scene_linear" ||
                      cs == "linear rec.709 (srgb)" || cs == "srgb-linear";
  if (!linear)
    throw file_error(path, "declares colour space '" + info.color_space + "', not the working space " + kWorkingSpace +
                               ": convert it first (no OpenColorIO conversion is built in)");
}

}  // namespace ahd

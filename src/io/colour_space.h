// Colour spaces as files declare them. ahdpack works in linear Rec.709 / sRGB primaries with a D65
// white (the working space the report records); float inputs that declare other primaries (EXR
// `chromaticities`) or a non-linear transfer (OpenImageIO's `oiio:ColorSpace`, e.g. "sRGB") are
// refused with one clear line rather than converted wrongly. (Conversion through OpenColorIO is
// not built in yet.) 8-bit inputs are baker data read as stored (direction, ratio, RGBM), not colour.
#pragma once
#include <string>

#include "io/image_io.h"

namespace ahd {

constexpr const char* kWorkingSpace = "linear Rec.709 (sRGB primaries, D65), scene-referred";

// Throws ahd::Error("<path>: <cause>") when a float image declares a colour space other than the
// working space: chromaticities more than 1e-3 from Rec.709's, or a non-linear oiio:ColorSpace.
void check_working_space(const ImageFileInfo& info, const std::string& path);

}  // namespace ahd

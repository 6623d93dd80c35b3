// Output profiles: which planes a conversion writes and in which formats. The standard profiles are
// built into the library (generated from formats/profiles/*.json at build time, so the library needs
// no data files and no environment); files/profile_file.h finds profiles on disk by name or path.
#pragma once
#include <string>
#include <vector>

#include "core/pixel_format.h"

namespace ahd {

struct Profile {
  std::string name;
  std::string description;
  PixelFormat iz = PixelFormat::RGBA16_SFLOAT;
  // Either separate dir + ratio planes, or one packed RGBA8 plane: RG = direction, B = ratio.
  bool packed_dir_ratio = false;
  PixelFormat dir = PixelFormat::RG8_UNORM;
  PixelFormat ratio = PixelFormat::R8_UNORM;
  PixelFormat dirratio = PixelFormat::RGBA8_UNORM;
  bool ratio_rgb = false;  // "ratio_form": "rgb" — C_a/I_z per channel instead of L(C_a)/L(I_z)
  // "dir_ratio_scale": 1, 2 or 4 (absent = 1). The dir and ratio planes (or the packed dirratio) are
  // ceil(W/s) x ceil(H/s), their mip chains starting there; I_z stays W x H. Decoders sample them
  // with the same UV (pipeline/lowres_planes.h; docs/engine-integration.md "The planes").
  int dir_ratio_scale = 1;
};

// Parses a profile's JSON text (untrusted: every field is checked). Throws
// ahd::Error("<path_for_errors>: <cause>").
Profile profile_from_json(const std::string& text, const std::string& path_for_errors);

// A standard profile by name ("uncompressed", "pc-bc", …). Throws ahd::Error listing the known
// names when there is none of that name.
Profile builtin_profile(const std::string& name);

// The standard profiles' names, sorted.
std::vector<std::string> builtin_profile_names();

}  // namespace ahd

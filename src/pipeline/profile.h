// Output profiles: which planes a conversion writes and in which formats (formats/profiles/*.json).
#pragma once
#include <string>
#include <vector>

#include "core/paths.h"
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
};

// Loads a profile by name (formats/profiles/NAME.json) or from a .json path. Throws ahd::Error
// naming the file and the problem.
Profile load_profile(const std::string& name_or_path);

// Names of the profiles in formats/profiles/, sorted.
std::vector<std::string> list_profiles();

}  // namespace ahd

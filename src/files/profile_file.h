// Finding output profiles on disk: by name in formats/profiles/ (files/paths.h), or a .json path.
#pragma once
#include <string>
#include <vector>

#include "pipeline/profile.h"

namespace ahd {

// A .json path is read and parsed; a name is looked up in formats/profiles/ and, when the folder
// has no such file (an installed tool without its data), among the built-in profiles. Throws
// ahd::Error naming the file and the problem.
Profile load_profile(const std::string& name_or_path);

// Names of the profiles in formats/profiles/ (the built-in ones when the folder is absent), sorted.
std::vector<std::string> list_profiles();

}  // namespace ahd

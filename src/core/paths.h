// Where the data files of the tool live (profiles, baker layouts, shaders).
#pragma once
#include <string>

namespace ahd {

// $AHD_FORMATS_DIR when set, else the source tree's formats/ folder.
std::string formats_dir();

}  // namespace ahd

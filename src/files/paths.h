// Where the data files of the tool live (profiles, baker layouts, shaders).
#pragma once
#include <string>
#include <vector>

namespace ahd {

// The install prefix of the running executable by the install's relative layout (<prefix>/bin/ahdpack
// → <prefix>), so that a prefix moved or copied elsewhere still finds its own files. Empty without
// /proc/self/exe.
std::string executable_prefix();

// The install prefix of the file holding this code by the same rule (<prefix>/<libdir>/libahd_cook.so
// → <prefix>): where a program linking the installed ahdpack::bakers or ahdpack::cook, whose own
// executable is elsewhere, finds the package's files. Tried after executable_prefix(). Empty when
// unknown.
std::string library_prefix();

// $AHD_FORMATS_DIR when set, else the installed data beside the executable (<prefix>/bin/ahdpack
// → <prefix>/share/ahdpack/formats) or beside the library (library_prefix) when it exists, else
// the source tree's formats/ folder.
std::string formats_dir();

// A named data file of formats/<folder>/ ("NAME" → formats/<folder>/NAME.json), or the path itself
// when it already names a .json file.
std::string data_file_path(const std::string& folder, const std::string& name_or_path);

// The names (without .json) of the data files in formats/<folder>/, sorted.
std::vector<std::string> list_data_files(const std::string& folder);

}  // namespace ahd

// Make/Ninja depfiles: what `convert --depfile` writes so a build system knows every file a
// conversion read (files/input_record.h) and rebuilds it when any of them changes.
#pragma once
#include <string>
#include <vector>

namespace ahd {

// "TARGET: \\\n  DEP1 \\\n  DEP2\n" with each dependency made absolute (Ninja resolves relative
// paths against its build folder, not the tool's working directory) and escaped as both Make and
// Ninja read it: space and '#' after a backslash, '$' doubled. The target is written as given
// (it must match the build rule's output as the build system names it). Throws ahd::Error for a
// path holding a newline (no depfile syntax can carry it).
std::string depfile_text(const std::string& target, const std::vector<std::string>& deps);

// depfile_text written to `path` through a temporary file and a rename. Throws ahd::Error naming
// the file.
void write_depfile(const std::string& path, const std::string& target, const std::vector<std::string>& deps);

}  // namespace ahd

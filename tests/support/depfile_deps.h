// The dependencies a depfile lists (the cook's depfile_text; test paths need no escapes).
#pragma once
#include <filesystem>
#include <set>
#include <sstream>
#include <string>

#include "file_bytes.h"

namespace ahd_test {

// Every path after "OUT.json:", without the line continuations.
inline std::set<std::string> depfile_deps(const std::filesystem::path& d) {
  std::istringstream in(read_text(d));
  std::set<std::string> deps;
  std::string tok;
  bool target = true;
  while (in >> tok) {
    if (target) {
      target = false;  // "OUT.json:"
      continue;
    }
    if (tok != "\\") deps.insert(tok);
  }
  return deps;
}

}  // namespace ahd_test

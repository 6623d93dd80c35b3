// Errors of the library: one type (ahd::Error, public: <ahd/types.h>), one line of text naming the
// file (when known) and the cause.
#pragma once
#include <ahd/types.h>
#include <string>

namespace ahd {

// Builds "<path>: <cause>" (or just the cause when path is empty).
inline Error file_error(const std::string& path, const std::string& cause) {
  return Error(path.empty() ? cause : path + ": " + cause);
}

}  // namespace ahd

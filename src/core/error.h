// Errors of the library: one type, one line of text naming the file (when known) and the cause.
#pragma once
#include <stdexcept>
#include <string>

namespace ahd {

// Every failure the library reports to a caller is an ahd::Error whose what() is a single
// line fit for a terminal: "<file>: <cause>" when a file is involved, otherwise just the cause.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Builds "<path>: <cause>" (or just the cause when path is empty).
inline Error file_error(const std::string& path, const std::string& cause) {
  return Error(path.empty() ? cause : path + ": " + cause);
}

}  // namespace ahd

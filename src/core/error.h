// Errors of the library: one type (ahd::Error, public: <ahd/types.h>), one line of text naming the
// file (when known) and the cause.
#pragma once
#include <ahd/types.h>
#include <string>

namespace ahd {

// A file name as it appears in an error line: control characters (a newline in a name would
// split the one-line error in two) become \n, \r, \t or \xNN; everything else is kept.
inline std::string printable_path(const std::string& path) {
  std::string out;
  out.reserve(path.size());
  for (const char ch : path) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c != 0x7F) {
      out += ch;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

// Builds "<path>: <cause>" (or just the cause when path is empty); Error's constructor escapes
// both, so the error stays one line whatever the file is called.
inline Error file_error(const std::string& path, const std::string& cause) {
  return Error(path.empty() ? cause : path + ": " + cause);
}

}  // namespace ahd

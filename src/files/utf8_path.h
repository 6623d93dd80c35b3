// UTF-8 strings ↔ std::filesystem::path. Paths travel through the program as UTF-8 std::string
// (argv is UTF-8 on Windows too: src/cli/win32/ahdpack.manifest); MinGW's libstdc++ converts
// path(std::string) and path::string() byte by byte whatever the code page, so a non-ASCII name
// turns into other characters there (docs/platforms.md "Windows"). These two go through
// std::u8string on Windows and are the plain conversions elsewhere (same bytes as before).
// Every place of the file edge that builds a path from a string, or a string from a path that
// later names a file or is printed, uses them.
#pragma once
#include <filesystem>
#include <string>

namespace ahd {

// The path named by the UTF-8 string `utf8`.
inline std::filesystem::path fs_path(const std::string& utf8) {
#ifdef _WIN32
  return std::filesystem::path(std::u8string(utf8.begin(), utf8.end()));
#else
  return std::filesystem::path(utf8);
#endif
}

// The UTF-8 string naming `p`.
inline std::string utf8_string(const std::filesystem::path& p) {
#ifdef _WIN32
  const std::u8string s = p.u8string();
  return std::string(s.begin(), s.end());
#else
  return p.string();
#endif
}

}  // namespace ahd

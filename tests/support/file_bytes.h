// Whole files as bytes, for the tests that corrupt, truncate or forge inputs.
#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

namespace ahd_test {

// The file's bytes; empty when it cannot be read.
inline std::vector<uint8_t> slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}
// The file's bytes as a string (text files too); empty when it cannot be read.
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}
// The names of the entries of a folder (files and folders, not recursive).
inline std::set<std::string> names_in(const std::filesystem::path& d) {
  std::set<std::string> s;
  for (const auto& e : std::filesystem::directory_iterator(d)) s.insert(e.path().filename().string());
  return s;
}
// Writes (replaces) the file with exactly these bytes.
inline void spit(const std::filesystem::path& p, const std::vector<uint8_t>& b) {
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}
inline void spit(const std::filesystem::path& p, const std::string& s) {
  spit(p, std::vector<uint8_t>(s.begin(), s.end()));
}
// Little-endian stores into a header being forged; `at` + width must be within b.
inline void wr32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = uint8_t(v >> (8 * i));
}
inline void wr64(std::vector<uint8_t>& b, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) b[at + i] = uint8_t(v >> (8 * i));
}
inline uint64_t rd64(const std::vector<uint8_t>& b, size_t at) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | b[at + size_t(i)];
  return v;
}

}  // namespace ahd_test

#include "bakers/unity/lightmap_page.h"
#include "files/utf8_path.h"

#include <cctype>
#include <filesystem>

namespace ahd {

namespace {

// The decimal number at s[i…] followed by '_', '.' or the end; −1 otherwise (or past 1e6).
int number_at(const std::string& s, size_t i) {
  size_t j = i;
  long v = 0;
  while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j])) && v < 1000000) v = v * 10 + (s[j++] - '0');
  if (j == i || v >= 1000000) return -1;
  if (j < s.size() && s[j] != '_' && s[j] != '.') return -1;
  return int(v);
}

}  // namespace

int lightmap_page_from_name(const std::string& path, std::string* why) {
  const std::string name = utf8_string(fs_path(path).filename());
  static const std::string unity = "Lightmap-";
  if (name.compare(0, unity.size(), unity) == 0) {
    const int n = number_at(name, unity.size());
    if (n >= 0) {
      if (why) *why = "Unity's file name Lightmap-" + std::to_string(n);
      return n;
    }
  }
  for (size_t at = name.find("_LM"); at != std::string::npos; at = name.find("_LM", at + 1)) {
    const int n = number_at(name, at + 3);
    if (n >= 0) {
      if (why) *why = "Bakery's file name _LM" + std::to_string(n);
      return n;
    }
  }
  return -1;
}

}  // namespace ahd

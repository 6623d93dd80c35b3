// How deeply untrusted JSON text nests, found before any recursive parser or printer sees it
// (nlohmann's parser and dump recurse once per level: a deep file overflows the stack).
#pragma once
#include <algorithm>
#include <cstddef>

namespace ahd {

// The deepest nesting of [ and { outside strings in p[0, n): a linear scan, no recursion. It stops
// once the depth passes `stop_after` (the caller's bound: any value above it is enough to refuse).
// Closing brackets that do not balance are ignored; the parser refuses them. Safe on any bytes.
inline size_t json_nesting_depth(const char* p, size_t n, size_t stop_after = ~size_t(0)) {
  size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < n && deepest <= stop_after; ++i) {
    const char c = p[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

}  // namespace ahd

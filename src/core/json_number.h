// Whole numbers from untrusted JSON. nlohmann's get<int>() / get<uint32_t>() convert a floating
// token such as 1e113 with undefined behaviour (found by fuzz_manifest under UBSan), so readers of
// files we did not write take integers only through these: integer tokens, range-checked.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/error.h"

namespace ahd {

// v as an integer in [lo, hi]; else ahd::Error("<path>: <what> must be a whole number in [lo, hi]").
inline int64_t json_whole(const nlohmann::json& v, int64_t lo, int64_t hi, const std::string& path, const std::string& what) {
  bool ok = v.is_number_integer();
  int64_t x = 0;
  if (ok && v.is_number_unsigned()) {
    const uint64_t u = v.get<uint64_t>();
    ok = u <= uint64_t(INT64_MAX);
    x = ok ? int64_t(u) : 0;
  } else if (ok) {
    x = v.get<int64_t>();
  }
  if (!ok || x < lo || x > hi)
    throw file_error(path, what + " must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return x;
}

// The member `key` of object j (json_whole), or `fallback` when j has no such member.
inline int64_t json_whole_or(const nlohmann::json& j, const char* key, int64_t fallback, int64_t lo, int64_t hi,
                             const std::string& path) {
  return j.contains(key) ? json_whole(j.at(key), lo, hi, path, key) : fallback;
}

}  // namespace ahd

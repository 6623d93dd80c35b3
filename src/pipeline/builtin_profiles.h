// The text of formats/profiles/*.json, compiled in (cmake/embed_profiles.cmake writes the table).
#pragma once
#include <cstddef>

namespace ahd {

struct BuiltinProfileText {
  const char* name;
  const char* json;
};
extern const BuiltinProfileText kBuiltinProfiles[];
extern const size_t kBuiltinProfileCount;

}  // namespace ahd

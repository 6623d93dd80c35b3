#include "bakers/godot/godot_unwrap_cache.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "files/input_file.h"

namespace ahd {

std::vector<GodotUnwrapEntry> parse_godot_unwrap_cache(const uint8_t* data, size_t size, const std::string& source) {
  size_t at = 0;
  const auto fail = [&](const std::string& why) -> Error {
    return file_error(source, "not a readable Godot unwrap cache (" + why + ")");
  };
  const auto word = [&]() -> uint32_t {
    if (size - at < 4) throw fail("truncated at byte " + std::to_string(at));
    uint32_t w;
    std::memcpy(&w, data + at, 4);  // little-endian hosts only (as Godot writes)
    at += 4;
    return w;
  };
  // A count of `words` 4-byte words each: at most what is left.
  const auto count = [&](uint32_t n, size_t words, const char* what) {
    if (int32_t(n) < 0 || size_t(n) > (size - at) / 4 / words)
      throw fail(std::string(what) + " count " + std::to_string(int32_t(n)) + " exceeds the file");
    return n;
  };
  std::vector<GodotUnwrapEntry> out;
  const uint32_t entries = count(word(), 8, "entry");
  for (uint32_t e = 0; e < entries; ++e) {
    GodotUnwrapEntry g;
    if (size - at < 16) throw fail("truncated at byte " + std::to_string(at));
    std::memcpy(g.hash, data + at, 16);
    at += 16;
    g.size_hint[0] = int32_t(word());
    g.size_hint[1] = int32_t(word());
    const uint32_t v = count(word(), 3, "vertex");
    g.source_vertex.resize(v);
    for (uint32_t i = 0; i < v; ++i) {
      g.source_vertex[i] = word();
      if (int32_t(g.source_vertex[i]) < 0) throw fail("negative source vertex");
      g.source_vertices = std::max(g.source_vertices, g.source_vertex[i] + 1);
    }
    g.uv2.resize(size_t(v) * 2);
    for (float& f : g.uv2) {
      const uint32_t w = word();
      std::memcpy(&f, &w, 4);
      if (!std::isfinite(f)) throw fail("non-finite UV2");
    }
    const uint32_t n = count(word(), 1, "index");
    if (n % 3 != 0) throw fail("index count " + std::to_string(n) + " is not a multiple of 3");
    g.indices.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
      g.indices[i] = word();
      if (g.indices[i] >= v) throw fail("index " + std::to_string(g.indices[i]) + " beyond " + std::to_string(v) + " vertices");
    }
    out.push_back(std::move(g));
  }
  if (at != size) throw fail(std::to_string(size - at) + " bytes after the last entry");
  return out;
}

std::vector<GodotUnwrapEntry> read_godot_unwrap_cache(const std::string& path) {
  const std::vector<uint8_t> bytes = read_input_bytes(path, InputKind::kUnwrapCache);
  return parse_godot_unwrap_cache(bytes.data(), bytes.size(), path);
}

}  // namespace ahd

// Godot's NAME.glb.unwrap_cache (parse_godot_unwrap_cache, issue 44): counts checked against the
// bytes left before anything is allocated, indices against the vertex count. What it accepts must
// hold those invariants (checked again here). Seeds: the small caches of tests/data/bakes.
#include "bakers/godot/godot_unwrap_cache.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ahd_fuzz::expect_clean([&] {
    const std::vector<ahd::GodotUnwrapEntry> entries = ahd::parse_godot_unwrap_cache(data, size, "f.glb.unwrap_cache");
    for (const ahd::GodotUnwrapEntry& e : entries) {
      if (e.uv2.size() != 2 * e.source_vertex.size() || e.indices.size() % 3 != 0) __builtin_trap();
      for (uint32_t i : e.indices)
        if (i >= e.source_vertex.size()) __builtin_trap();
      for (uint32_t s : e.source_vertex)
        if (s >= e.source_vertices) __builtin_trap();
    }
  });
  return 0;
}

// Lightmap users of a Godot project that the reader could not place (GodotSceneMeshes::unplaced:
// a cache entry Godot dropped, a TextMesh, a GridMap cell, a missing file): the line that refuses
// them by default, and --allow-unplaced's fallback for their texels (docs/godot.md "Users that
// cannot be placed").
#pragma once
#include <ahd/types.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

struct GodotSceneMeshes;

// One line: how many users cannot be placed, which (grouped by cause: three causes, three users
// each, then counts), why, and the remedy. Pure.
std::string godot_unplaced_refusal(const GodotSceneMeshes& g);

// Texels (1) of page `page`, a w × h lightmap, inside the atlas rectangles of g's unplaced users
// and not `covered` (w × h) by a placed mesh; empty when no user is unplaced. Pure.
std::vector<uint8_t> godot_unplaced_texels(const GodotSceneMeshes& g, int page, const std::vector<uint8_t>& covered,
                                           int w, int h);

// The fallback: each lit texel of `fallback` (any stored SH number non-zero, sh->coverage set) is
// kept covered with, as its normal, the direction of its own luminance L1 band (the light's mean
// direction: the best guess of the surface normal the SH alone gives) and marked covered in
// *mesh_coverage; unlit ones are left uncovered. Returns how many were kept.
size_t keep_godot_unplaced_texels(const std::vector<uint8_t>& fallback, ShImage* sh,
                                  std::vector<uint8_t>* mesh_coverage);

}  // namespace ahd

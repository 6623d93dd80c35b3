// The input of a conversion, as `convert` and `verify` take it and as a cook reads it: the
// canonical SH EXR, a baker's files through a layout preset (auto-detected, or `layout`), with
// normals from a normal map, a mesh (and its placement) or the baker's own scene (a Godot project),
// one page or every page of a stacked atlas; or, with no input, the built-in sample. One reader so
// that a cook's gate (`verify`) reads exactly what its conversion read.
//
// The command-line flags of these fields are declared once, in bake_input_options() below; the CLI
// only adds them to its parser (it names no baker).
#pragma once
#include <ahd/bakers.h>

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "image/sh_exr.h"
#include "sh/sh_image.h"

namespace ahd {

struct GodotSceneMeshes;

// The public fields (input, layout, normals, mesh, …, the sample's size/order/seed) are those of
// <ahd/bakers.h> BakeSource; what reading keeps between calls is added here.
struct BakeInput : BakeSource {
  mutable std::shared_ptr<const GodotSceneMeshes> godot;  // the scene, loaded once for every page
  // What reading found (detection, pages, overlaps), printed once the input has been read, so that
  // a failure prints its one error line and nothing else.
  mutable std::string notes;
  // The atlas page --placement selects for a one-page file: `page`, or the file name's
  // (bakers/unity/lightmap_page.h), else 0. Set by read_bake_pages.
  mutable int placement_page = 0;
  mutable int page_count_of_input = 0;  // the pages read_bake_pages found (1: a one-page file)
};

// One command-line option of a BakeInput field: its flag, help, the field, and the least value an
// integer takes (CLI checks). The CLI adds every row; the cache key names every field.
struct BakeInputOption {
  const char* flag;
  std::variant<std::string BakeInput::*, int BakeInput::*, bool BakeInput::*> field;
  std::string help;
  int min_value = 0;  // integers: the least valid value
};

// --layout, --pages, --normals, --mesh, --node, --uv-set, --placement, --page, --godot-scene, --input-space,
// --allow-mismatch, --allow-unplaced (the input itself is the caller's positional argument; the sample's options
// are convert's).
const std::vector<BakeInputOption>& bake_input_options();

// `layout` "auto", and the default for an input that is not the canonical EXR: the baker's set is
// detected from the files present and their contents, and what was found goes to a->notes.
// Without a layout, an input nothing recognises goes to the canonical reader (its errors).
// `layout` "plain" on a Godot atlas of stacked layers (NAME.exr.import: 2d_array_texture,
// slices/vertical > 1) throws ahd::Error("<exr>: is a Godot directional SH atlas …") naming the
// detected preset and the remedy: plain would read the stack as one lightmap.
void resolve_auto_layout(BakeInput* a);

// A world-space bake without normals, mesh or scene: the baker's scene that baked it (a Godot
// project's .tscn beside the EXR), then a->scene is set and a note says so. Call after
// resolve_auto_layout.
void find_scene_for_input(BakeInput* a);

// Throws ahd::Error for options that contradict each other (mesh with normals, …), before
// anything is read.
void check_bake_input(const BakeInput& a);

// The scale at which the input's numbers are stored, for `convert --iz-scale` left to the input:
// 1/π for a plain lightmap (its numbers are E/π, what engines multiply by albedo: the I_z plane then
// holds them unchanged), 1 (irradiance) for everything else. Call after resolve_auto_layout.
// *why (optional): one line for the notes when it is not 1.
double input_iz_scale(const BakeInput& a, std::string* why = nullptr);

// The input's atlas pages: one, unless a paged layout (Godot) holds several — then every page, in
// order. *source describes what was read (for the summary and the report). `threads` bakes the
// sample. Throws ahd::Error("<file>: <cause>"). Every file opened is noted in the current input
// record (files/input_record.h).
std::vector<ShImage> read_bake_pages(const BakeInput& a, int threads, ReadStats* rs, std::string* source);

// The input read as `convert` reads it, in its order: resolve_auto_layout, find_scene_for_input,
// check_bake_input, read_bake_pages. For commands that read a conversion's source again (verify,
// preview): the same options give the same pages. *a is updated as those calls update it (layout,
// base path, scene, notes). Throws ahd::Error("<file>: <cause>").
std::vector<ShImage> read_bake_input(BakeInput* a, int threads, ReadStats* rs, std::string* source);

}  // namespace ahd

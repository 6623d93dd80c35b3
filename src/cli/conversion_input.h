// The input of a conversion, as `convert` and `verify` take it: the canonical SH EXR, a baker's
// files through a layout preset (auto-detected, or --layout), with --normals or --mesh (and
// --placement) for the normals and coverage, one page or every page of a stacked atlas; or, with no
// input, the built-in sample. One reader so that a cook's gate (`verify`) reads exactly what its
// conversion read.
#pragma once
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "io/sh_exr.h"
#include "sh/sh_image.h"

namespace ahd {
struct GodotSceneMeshes;
}

namespace ahd::cli {

struct InputArgs {
  std::string input;      // "" = the built-in sample
  std::string layout;     // baker layout preset (name or .json); input is then the base path
  std::string normals;    // lightmap-space normals for world-space layouts
  std::string mesh;       // or: the mesh, rasterised in its lightmap UVs (normals and coverage)
  int uv_set = -1;        // the mesh's lightmap UV set (−1 = the default rule of io/mesh_io.h)
  int pages = 0;          // atlas pages of a paged layout (0 = as recorded by the baker)
  std::string placement;  // per-instance atlas placement of the mesh (JSON or Unity scene)
  std::string godot_scene;  // or: a Godot scene (.tscn) whose LightmapGI baked the input
  bool allow_mismatch = false;  // convert even when the mesh's coverage disagrees with the lightmap
  std::string input_space;      // --input-space: the input's colour space, replacing its declaration ("" = as declared)
  mutable std::shared_ptr<const GodotSceneMeshes> godot;  // the scene, loaded once for every page
  int sample_size = 256;
  int sample_order = 2;
  unsigned seed = 0;
  // What reading found (detection, pages, overlaps), printed once the input has been read, so that
  // a failure prints its one error line and nothing else.
  mutable std::string notes;
};

// --layout, --pages, --normals, --mesh, --uv-set, --placement, --godot-scene, --allow-mismatch, --input-space (the input itself is the caller's
// positional argument; the sample's options are convert's).
void add_input_options(CLI::App* c, InputArgs* a);

// --layout auto, and the default for an input that is not the canonical EXR: the baker's set is
// detected from the files present and their contents, and what was found goes to a->notes.
// Without --layout, an input nothing recognises goes to the canonical reader (its errors).
void resolve_auto_layout(InputArgs* a);

// A Godot world-space bake without normals: the scene that baked it, when it lies beside the EXR
// (then a->godot_scene is set and a note says so). Call after resolve_auto_layout.
void find_godot_scene_for_input(InputArgs* a);

// Throws ahd::Error for options that contradict each other (--mesh with --normals, …), before
// anything is read.
void check_input_args(const InputArgs& a);

// The input's atlas pages: one, unless a paged layout (Godot) holds several — then every page, in
// order. *source describes what was read (for the summary and the report). `threads` bakes the
// sample. Throws ahd::Error("<file>: <cause>"). Every file opened is noted in the current input
// record (io/input_record.h).
std::vector<ShImage> read_input_pages(const InputArgs& a, int threads, ReadStats* rs, std::string* source);

}  // namespace ahd::cli

// ahdpack's baker reader: a baker's files on disk → the SH image a conversion takes (<ahd/convert.h>),
// with its normals and coverage. Link ahdpack::bakers (a shared library; it brings ahdpack::ahd).
//
// What it reads, exactly as `ahdpack convert` reads it (same images, same bytes converted):
// - the canonical SH EXR (sh0.R … sh8.B);
// - any file of a baker's set through a layout preset (formats/bakers/*.json: Bakery, Godot,
//   Unity, EXR layers…), named in `layout` or detected from the files present ("" or "auto");
// - a Godot project's LightmapGI bake: its pages, and the normals and coverage rasterised from the
//   scene's meshes in their lightmap UVs (the .tscn beside the EXR is found on its own);
// - a world-space bake's normals from a normal map (`normals`), or a mesh (`mesh`, with its
//   per-instance atlas `placement`) rasterised in its lightmap UVs;
// - with no input, the built-in analytic sample.
//
// Data files: layout presets and profiles named (not given as .json paths) are looked up in
// $AHD_FORMATS_DIR, else <prefix>/share/ahdpack/formats of the installed package, else the build
// tree's formats/. Images other than EXR are read through OpenImageIO's module
// (<prefix>/lib/ahdpack/libahd_oiio.so), loaded on first use.
#pragma once
#include <ahd/export.h>
#include <ahd/convert.h>  // LightmapInstance
#include <ahd/types.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

// What to read: the input options of `ahdpack convert` (`ahdpack convert --help`), field for field.
// `struct_size` guards against a header and a library from different versions: leave it as
// initialised; the library throws ahd::Error when it differs from its own sizeof.
struct BakeSource {
  uint32_t struct_size = sizeof(BakeSource);
  std::string input;      // "" = the built-in sample; else the canonical EXR or any file of a baker's set
  std::string layout;     // baker layout preset (name or .json; "" or "auto": detected); input is then the base path
  std::string normals;    // lightmap-space normals for world-space layouts
  std::string mesh;       // or: the mesh, rasterised in its lightmap UVs (normals and coverage)
  int uv_set = -1;        // the mesh's lightmap UV set (−1 = the default rule: the second set, else the first)
  int pages = 0;          // atlas pages of a paged layout (0 = as recorded by the baker)
  std::string placement;  // per-instance atlas placement of the mesh (JSON or Unity scene)
  std::string scene;      // or: the baker's scene (a Godot .tscn, or its editor's glTF export)
  bool allow_mismatch = false;  // convert even when the mesh's coverage disagrees with the lightmap
  std::string input_space;      // the input's colour space, replacing its declaration ("" = as declared)
  int sample_size = 256;        // the built-in sample: width and height
  int sample_order = 2;         // the built-in sample: SH order 1 (L1) or 2 (L2)
  unsigned seed = 0;            // the built-in sample: scene seed (0 = canonical)
  // Godot: convert even when some lightmap users cannot be placed (their lit texels kept, fitted
  // about their own L1 direction, and counted; docs/godot.md "Users that cannot be placed").
  bool allow_unplaced = false;
  // Per-object lightmaps (Bevy): the one glTF node (or mesh) of `mesh` the lightmap belongs to,
  // by its node name or its mesh name; "" = every node of the mesh file.
  std::string node;
  // The atlas page of a one-page file, for `placement` (−1 = from the file name: Unity
  // `Lightmap-N_…`, Bakery `…_LMN_…`; else 0).
  int page = -1;
};

// An existence test a reader's decision rested on (is NAME.exr.import beside it? which baker's
// files are present?): `type` is std::filesystem::file_type of the path when probed (not_found =
// absent). A cache replays them to reuse a conversion without reading its images (<ahd/cook.h>).
struct InputProbe {
  std::string path;
  int type = 0;
  bool operator==(const InputProbe&) const = default;
};

// What was read.
struct BakeRead {
  uint32_t struct_size = sizeof(BakeRead);
  // The atlas pages in order: one, unless a paged layout (Godot) holds several. Each in the working
  // space (linear Rec.709, irradiance SH), with normals (world-space bakes) and coverage when known.
  std::vector<ShImage> pages;
  std::string source;              // what was read, one line (the summary's and the report's "source")
  std::string notes;               // what detection found and decided, lines ending in '\n' (may be empty)
  size_t non_finite_texels = 0;    // NaN/Inf texels zeroed and marked uncovered
  bool coverage_derived = false;   // no coverage channel: all-zero SH counted as uncovered
  std::string input_space;         // the space the input was converted from ("" = read as the working space)
  std::vector<std::string> files;  // every file read, in order, each once, as named (a depfile's list)
  std::vector<InputProbe> probes;  // every existence test made, in order
  // The placed scene's lightmapped instances (a Godot project's users, a mesh with its placement);
  // empty otherwise. Hand them to ahd::convert to write the manifest `ahdpack convert` writes.
  std::vector<LightmapInstance> instances;
};

// Reads `source` (see above). `threads` bakes the sample (0 = all hardware threads).
// Contract: throws ahd::Error("<file>: <cause>") for a missing, unreadable or inconsistent file,
// and for options that contradict each other (a mesh with normals, …) before anything is read.
// Safe on untrusted files (every reader bounds its sizes). Reentrant: different calls may run on
// different threads at once (the record of files read is per thread). Reads no environment
// variable but AHD_FORMATS_DIR.
AHD_API BakeRead read_bake(const BakeSource& source, int threads = 0);

// The layout presets (formats/bakers) by name, sorted, and those `layout` "auto" recognises.
AHD_API std::vector<std::string> bake_layouts();
AHD_API std::vector<std::string> auto_detected_bake_layouts();

}  // namespace ahd

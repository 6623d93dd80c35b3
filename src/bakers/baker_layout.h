// Reading SH lightmaps from any baker through declarative layout presets (formats/bakers/*.json,
// schema in formats/bakers/SCHEMA.md): which files, which layer and channel hold which
// coefficient, how stored values decode, and how they are normalised. Everything is converted on
// read into the tool's one canonical form (sh/sh.h).
#pragma once
#include <string>
#include <vector>

#include "image/sh_exr.h"
#include "sh/sh_image.h"

namespace ahd {

// One image of the set: a file, or one part of a multi-part EXR (OIIO subimage).
struct LayoutFile {
  std::string pattern;    // "{base}" is replaced by the base path
  int slices = 1;         // layers stacked vertically in the image
  bool needs_float = false;
  int part = 0;           // part index, used when part_name is empty
  std::string part_name;  // the part's name (EXR "name" attribute)
  bool per_page = false;  // `slices` is per atlas page: the image stacks pages × slices layers, page-major
  bool srgb = false;      // "encoding": "srgb": its colour channels are sRGB-encoded (decoded on read)
};

// Where one stored number comes from: an image of the set, its vertical layer, a channel name
// (with the EXR layer prefix if any, e.g. "L1m1.R").
struct LayoutSource {
  int file = 0, slice = 0;
  std::string channel;
};

// One canonical coefficient, decoded per colour c from source[c] as
//   v = t (raw) or (t − 0.5)·k·L0 (ratio; L0 = coefficient 0 decoded), then v·scale / max(min, divisor)
//   · multiplier_scale · m^multiplier_power (RGBM: m = the stored alpha)
// so that colours may share a stored number (Bakery MonoSH, Unity directional) or come from
// different files (one file per colour).
struct LayoutCoefficient {
  LayoutSource source[3] = {{0, 0, "R"}, {0, 0, "G"}, {0, 0, "B"}};
  bool ratio = false;
  double k = 1;
  double scale = 1;
  bool divided = false;  // divide by a stored number (Unity's rebalancing alpha)
  LayoutSource divisor;
  double divisor_min = 0;
  bool multiplied = false;  // multiply by scale · stored^power (RGBM's range · alpha)
  LayoutSource multiplier;
  double multiplier_scale = 1, multiplier_power = 1;
};

enum class LayoutForm {
  Radiance,       // stored = the canonical radiance-SH projection
  LinearOverPi,   // stored (L0, L1) with E(n)/π = L0 + L1·n  (L1 in the stored coefficient order)
};

struct LayoutPreset {
  std::string name, description;
  bool canonical = false;  // the tool's own EXR (read_canonical_sh)
  int coeffs = 4;
  bool world_space = false;
  // How the baker's world axes relate to glTF's (right-handed, +y up), for normals rasterised from a
  // mesh (--mesh): baker component i = mesh_sign[i] · glTF component mesh_axis[i]. Identity for
  // Godot; Unity-world bakers (Bakery, Unity) are left-handed: x negated, as Unity's glTF exporters do.
  int mesh_axis[3] = {0, 1, 2};
  int mesh_sign[3] = {1, 1, 1};
  LayoutForm form = LayoutForm::Radiance;
  std::vector<LayoutFile> files;
  std::vector<LayoutCoefficient> coefficients;  // canonical order 0..n−1 (missing ones are 0)
  int page_count = 0;  // set by layout_page (bakers/layout_pages.h); 0: not chosen, read_layout checks for one page
  // Set by the reader's caller, not the preset: the colour space of every file of the set
  // (--input-space, image/colour_space.h), replacing what the files and the preset declare; "" = as declared.
  std::string input_space;
};

// Loads a preset by name (formats/bakers/NAME.json) or from a .json path. Throws ahd::Error naming
// the file and the problem.
LayoutPreset load_layout(const std::string& name_or_path);

// Names of the presets in formats/bakers/, sorted.
std::vector<std::string> list_layouts();

// The base path of a set given either as its base ("/bakes/room") or as any file of the set, the
// name users see ("/bakes/room_L1x.tga", "World.exr", "Lightmap-0_comp_light.exr"): when the first
// file of the set does not exist for `input` taken as a base but `input` ends with one of the
// preset's file suffixes, the longest such suffix is removed. Otherwise `input` is returned
// unchanged (the reader's checks then name what is missing). read_layout and layout_size apply it.
std::string layout_base(const LayoutPreset& layout, const std::string& input);

// Reads a baker's files for `base` (e.g. "/bakes/room" → "/bakes/room_L0.hdr" …). World-space
// layouts need `normals_path`: a normal EXR in lightmap space (XYZ, unit, world axes of the baker).
// Every image of the set is checked from its header before any pixel is decoded: throws
// ahd::Error("<file>: <cause>") for a missing file, a part the file lacks, sizes that differ, a layer
// count that does not divide, 8-bit data where float is needed, a missing channel, a colour space
// that cannot be converted or float files declaring different ones; also zero normals.
// Colour (docs/colour.md): the set's colour planes — the channels coefficient 0 reads, unless a
// ratio, divisor or multiplier reads them too — are decoded from sRGB when their file's entry says
// "encoding": "srgb" or its float header declares sRGB; then the SH is converted to the working
// space from the primaries the float files declare. layout.input_space replaces both declarations.
ShImage read_layout(const LayoutPreset& layout, const std::string& base, const std::string& normals_path,
                    ReadStats* stats = nullptr);

// Lightmap-space normals given in memory (e.g. rasterised from a mesh): `normals` is width×height×3
// (any length; normalised here, zero ones refused), `coverage` empty or width×height (1 = covered;
// replaces the coverage derived from zero SH). `source` names them in errors.
struct LayoutNormals {
  std::string source;
  int width = 0, height = 0;
  std::vector<float> normals;
  std::vector<uint8_t> coverage;
};
ShImage read_layout(const LayoutPreset& layout, const std::string& base, const LayoutNormals* normals,
                    ReadStats* stats = nullptr);

// Brings normals given in glTF's axes (a mesh) into the baker's world axes (the layout's
// mesh_axes), in place: 3 floats per texel.
void mesh_normals_to_layout_axes(const LayoutPreset& layout, std::vector<float>* normals);

// The lightmap's width and height (one layer), from the header of the set's first file — what
// in-memory normals must match before the set is read. Throws ahd::Error as read_layout does for
// a missing or unreadable file.
void layout_size(const LayoutPreset& layout, const std::string& base, int* width, int* height);

}  // namespace ahd

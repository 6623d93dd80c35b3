// A conversion read back for `preview` and `verify`: its manifest and every mip level decoded, and
// per-texel errors against the source SH (the same figures as fit/hemisphere_error.h, per texel).
#pragma once
#include <string>
#include <vector>

#include "bakers/bake_input.h"
#include "fit/hemisphere_error.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "sh/sh_image.h"

namespace ahd::cli {

struct ConversionView {
  Manifest manifest;
  // levels[l]: the planes of mip level l, array layer `layer`, with iz in units of E: the stored
  // I_z divided by the manifest's iz_scale (stored I_z = iz_scale × E, docs/godot.md "Irradiance scale").
  std::vector<DecodedPlanes> levels;
};

// Reads the manifest and every plane (sizes and SHA-256 checked by read_manifest_plane), and
// decodes each level of array layer `layer`. Throws ahd::Error("<file>: <cause>").
ConversionView read_conversion(const std::string& manifest_path, int layer = 0);

// The conversion's source read as convert read it (bakers/bake_input.h read_bake_input: the
// canonical EXR, any file of a baker's set, a Godot project with its scene…), one ShImage per
// atlas page, checked against the manifest's pages and size. *described says what was read.
// Throws ahd::Error naming the file as the user gave it. `read_as` (optional) receives the input
// as read (its Godot scene loaded: bakers/scene_export.h takes it).
std::vector<ShImage> read_source_for(BakeInput source, const Manifest& m, std::string* described,
                                     BakeInput* read_as = nullptr);

// Per texel of level 0 (row-major; NaN where the source is not covered):
//   hemisphere  RMS over 64 hemisphere normals and the channels of I − E / mean luminance of E
//   normal      |I(z) − E(z)| (max channel) / luminance of E(z)  — what quantisation adds
struct TexelErrorMaps {
  std::vector<float> hemisphere, normal;
};
TexelErrorMaps texel_error_maps(const ShImage& sh, const DecodedPlanes& level0, double dz_min);

// The ErrorReport of level 0 against the source (measure_error over every covered texel).
ErrorReport measure_conversion(const ShImage& sh, const DecodedPlanes& level0, double dz_min);

}  // namespace ahd::cli

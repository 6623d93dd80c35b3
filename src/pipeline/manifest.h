// The JSON manifest written beside every conversion: which files hold which plane, in which
// format, and every parameter a decoder needs. Versioned: readers refuse versions they don't know.
#pragma once
#include <string>
#include <vector>

#include "core/pixel_format.h"
#include "core/texture.h"
#include "fit/ahd_fit.h"

namespace ahd {

constexpr int kManifestVersion = 1;

struct ManifestPlane {
  std::string name;  // iz | dir | ratio | dirratio
  std::string file;  // relative to the manifest's folder
  PixelFormat format = PixelFormat::RGBA16_SFLOAT;
  uint32_t width = 0, height = 0, levels = 1;
  uint64_t bytes = 0;   // the file's exact byte size
  std::string sha256;   // the file's SHA-256 (hex): a plane replaced by another run is detected
  uint32_t layers = 1;  // array layers (atlas pages); written only when > 1
};

// A lightmapped instance of the scene the conversion was read with (a Godot project, --mesh with
// --placement): where its lightmap UVs land in the atlas. atlas_uv = uv2 · scale + offset, both in
// glTF's UV convention (origin top-left, v down: row 0 of the plane is v = 0; Godot's uv_scale
// rectangle is scale = (w, h), offset = (x, y)). docs/container-format.md "Instances".
struct ManifestInstance {
  std::string node;  // the node path (Godot, as the .lmbake names it) or the renderer / node name
  int page = 0;      // atlas page = array layer of every plane
  double scale[2] = {1, 1}, offset[2] = {0, 0};
};

struct Manifest {
  int version = kManifestVersion;
  std::string profile;
  std::string container;  // ktx2 | dds
  uint32_t width = 0, height = 0, levels = 1;
  uint32_t layers = 1;  // atlas pages, one array layer each (layer p = page p); written only when > 1
  std::vector<ManifestPlane> planes;
  RatioForm ratio_form = RatioForm::Luminance;
  double dz_min = 0.05;
  double luma[3] = {0.2126, 0.7152, 0.0722};
  std::string direction_encoding = "hemi-octahedral";  // uv = (px+py, px−py), p = d.xy/|d|₁
  std::string direction_frame = "tangent";             // or "normal-frame" (world SH + normals)
  // Stored I_z = iz_scale × E (E = irradiance, no 1/π): 1 stores E, 1/π stores E/π (convert --iz-scale).
  double iz_scale = 1.0;
  // false: only the iz plane exists; decoders use d = (0, 0, 1), ratio = 1, so I(n) = I_z.
  bool directional = true;
  // The scene's lightmapped instances (empty = not known: no placement in the input; not written).
  std::vector<ManifestInstance> instances;
};

std::string manifest_to_json(const Manifest& m);

// The rule for a plane's file name in a manifest (and so for a set's NAME, io and cli): a plain name
// beside the manifest — not empty, not hidden, no '/', '\\', ':' or NUL.
bool is_plain_file_name(const std::string& s);

// Parses and validates as strictly as a container: known, unique plane roles whose formats fit them
// (plane_format_problem), plain file names beside the manifest, every plane of the manifest's size
// and level count, sizes within max_image_size(), a byte size and SHA-256 per plane. Throws
// ahd::Error("<path>: <cause>").
Manifest manifest_from_json(const std::string& text, const std::string& path);

// Why format `f` cannot hold plane `role` (iz: HDR, 3+ channels; dir: UNORM, 2+; ratio: UNORM, 1+,
// 3+ for the RGB ratio; dirratio: UNORM, 3+; coverage: UNORM, 1+), or "" when it can. Decoders rely on it to stay in
// bounds.
std::string plane_format_problem(const std::string& role, PixelFormat f, RatioForm form);

// Why these fit parameters cannot be written into a manifest that decode accepts (dz_min in
// (0, 1), each luma weight in [0, 1], not all zero), or "" when they can. The one rule shared by
// manifest_from_json, read_intermediate and the writers: ahdpack never writes what it refuses.
std::string fit_parameters_problem(double dz_min, const double luma[3]);


// The key/value pairs every plane texture carries (KTX2 key/value data), describing the encoding.
std::vector<std::pair<std::string, std::string>> plane_metadata(const Manifest& m, const std::string& plane);

}  // namespace ahd

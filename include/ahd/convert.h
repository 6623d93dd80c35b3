// ahdpack's C++ entry point: an SH lightmap in memory → the finished conversion in memory (every
// plane container, the manifest and the report, as bytes with their file names). Link ahdpack::ahd.
//
// Contract:
// - Pure: no file system, no environment, no global state. The caller owns the input; the result
//   owns its bytes. Safe to call from several threads at once on different inputs.
// - Deterministic: the same input and options give the same bytes, whatever `threads` is.
// - Errors: throws ahd::Error (one line: the cause) on invalid options or input (sizes, coefficient
//   count, non-finite values are counted and zeroed, not errors); ahd::Cancelled when `cancel` rises.
// - Untrusted input: `sh` is only read within width*height*coeffs*3 floats after its size is
//   checked against data.size(); the profile JSON is parsed defensively.
#pragma once
#include <ahd/types.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ahd {

struct ConversionOptions {
  // Output profile: a standard one by name ("uncompressed", "uncompressed-rgb", "pc-bc", "pc-bc-half",
  // "pc-bc-quarter", "packed-float", "packed-rgb9e5"; docs/container-format.md "Outputs"), or, when `profile_json` is not empty, that
  // definition (the format of formats/profiles/*.json).
  std::string profile = "uncompressed";
  std::string profile_json;
  // The ratio plane's form; unset: the profile's (luminance unless the profile says rgb).
  std::optional<RatioForm> ratio;
  // How d is chosen: Refined (the default) picks, texel by texel, the d and ratio of lowest
  // hemisphere error, which tracks path-traced lighting best, noisy bakes included
  // (docs/accuracy-real-lighting.md); Linear is the paper's choice, about a third of the fit's time.
  DirectionFit direction_fit = DirectionFit::Refined;
  Bc6hQuality bc6h_quality = Bc6hQuality::Default;  // for profiles with BC6H planes
  int threads = 0;            // worker threads, 0 = all hardware threads
  double eps = 0.05;          // the horizon rule: smallest stored d_z, in (0, 1)
  bool closed_loop = true;    // refit the ratio against the decoded direction and I_z
  int levels = 0;             // mip levels to write, 0 = the full chain down to 1×1
  bool coverage_plane = false;  // also write NAME.coverage.<ext> (R8, 255 = covered)
  DirectionPlanes direction = DirectionPlanes::Auto;
  double ambient_threshold = 0.01;  // Auto: drop dir/ratio when I_z alone is within this (rel. p99)
  ContainerKind container = ContainerKind::KTX2;
  bool zstd = false;  // KTX2 Zstandard supercompression
  // ahd.* key/value metadata in every KTX2 plane (the manifest holds the same). Khronos'
  // `ktx validate` warns once per unknown key, so its strict mode (-e) rejects such files: set
  // false for files that pass strict validation.
  bool plane_metadata = true;
  Measure measure = Measure::Off;  // error diagnostics in the report (they cost time)
  // Stored I_z = iz_scale × E (E: the irradiance the SH gives; 1/π stores E/π, what most engines'
  // lightmaps hold). The SH is scaled before the fit: d and the ratio do not change. Recorded in the
  // manifest and the planes (`iz_scale`), which decoders divide by. > 0; the cook (<ahd/cook.h>) also
  // takes 0: the input's own scale (a plain lightmap's E/π: 1/π; else 1).
  double iz_scale = 1.0;
  // Plane files named NAME.<plane>.<ext>, without the content hash, so that an engine's references
  // to them (Godot res:// paths, Unity .meta GUIDs) survive a re-cook. docs/asset-cook.md "Stable
  // names for engines" says what publishing them keeps and what it gives up.
  bool stable_names = false;
  // Called on the calling thread between steps with a stage name ("fit", "encode", "write"; the
  // error measures report no progress of their own) and the fraction of that stage done, in [0, 1].
  std::function<void(const char* stage, double fraction)> progress;
  // When not null and raised (from any thread), the conversion stops with ahd::Cancelled.
  const std::atomic<bool>* cancel = nullptr;
};

// A lightmapped instance of the scene a bake was read with (<ahd/bakers.h> BakeRead::instances),
// written to the manifest's "instances" by the convert overload that takes them
// (docs/container-format.md "Instances"): where its lightmap UVs land in the atlas.
struct LightmapInstance {
  std::string node;  // Godot: the node path as the .lmbake names it; else the renderer / node name
  int page = 0;      // atlas page = array layer of every plane
  // atlas_uv = uv2 * uv_scale + uv_offset, glTF UV convention (v down, v = 0 is row 0)
  double uv_scale[2] = {1, 1}, uv_offset[2] = {0, 0};
};

// One output file: its name (no folder) and its bytes.
struct OutputFile {
  std::string name;
  std::vector<uint8_t> bytes;
};

struct Conversion {
  // The plane containers (NAME.<plane>.<hash>.<ext>: iz, dir, ratio…, named by the first 12 hex
  // digits of their SHA-256 so a new set never overwrites the planes an older manifest names;
  // NAME.<plane>.<ext> with stable_names), then
  // NAME.report.json (rules fired, errors, seconds), then NAME.json (the manifest: which file holds
  // which plane, its size and SHA-256, and how to decode it). Write the manifest last.
  std::vector<OutputFile> files;
  bool directional = true;  // false: only the iz plane was written (see DirectionPlanes)
};

// Converts `sh` into planes named after `name` (a file stem such as "room": no folder, no dots
// needed). See the contract above.
AHD_API Conversion convert(const ShImage& sh, const std::string& name, const ConversionOptions& options = {});
// The same, taking the image over: it becomes mip level 0 without a copy (peak memory ≈ 2.4× the
// SH instead of 3.4× for L2). `sh` is left empty.
AHD_API Conversion convert(ShImage&& sh, const std::string& name, const ConversionOptions& options = {});
// The same, the manifest also listing the scene's lightmapped `instances` (<ahd/bakers.h>
// BakeRead::instances; each page must be a page of the conversion), as `ahdpack convert` writes it.
// Throws ahd::Error for an instance on a page the conversion does not have.
AHD_API Conversion convert(const ShImage& sh, const std::string& name, const ConversionOptions& options,
                           const std::vector<LightmapInstance>& instances);

}  // namespace ahd

// `--layout auto`: which baker wrote a set of files, from the files present beside the one given
// (Godot's import file, project and .lmbake; Bakery's and Unity's suffixes), and their contents
// (EXR channel and part names; the sign of Godot's L1 layers).
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace ahd {

struct LayoutDetection {
  std::string preset;                // a preset name of formats/bakers/
  std::string base;                  // the set's base path
  std::vector<std::string> reasons;  // why, one fact per entry, for the user
  std::vector<std::string> notes;    // files seen and ignored (e.g. a shadowmask)
};

// Detects the layout of the set holding `input` (any file of the set, or its base). When no
// baker's set matches, a lone EXR of exactly R, G, B (A) channels is a plain lightmap and a lone
// KTX2 texture plain-ktx2 (the reason says so). Throws
// ahd::Error("<input>: <cause>") when nothing matches, or when several presets fit and the files
// cannot tell them apart (the message lists the candidates and what would decide).
LayoutDetection detect_layout(const std::string& input);

// The same, but nothing recognised is not an error (std::nullopt); ambiguity still throws.
std::optional<LayoutDetection> try_detect_layout(const std::string& input);

// The presets detect_layout can answer, sorted (for `ahdpack layouts`).
std::vector<std::string> auto_detected_layouts();

// Whether `path` is the tool's canonical EXR (an existing image with an sh0.R channel).
bool is_canonical_sh_file(const std::string& path);

// Why a file found in a batch folder is not a lightmap, from its name ("" when it may be one):
// Unity writes its reflection probes (`ReflectionProbe-N.exr`) beside the lightmaps. Pure.
std::string not_a_lightmap_reason(const std::string& path);

}  // namespace ahd

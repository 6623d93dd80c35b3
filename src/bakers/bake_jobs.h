// A batch job file: one conversion per lightmap, each with its own input options — what a
// per-object baker's level needs (Bevy: one KTX2 per object, each the lightmap of one node of the
// scene's glTF). `ahdpack convert --jobs FILE -o OUTDIR/`.
//
//   {"jobs": [{"input": "CornellBox-Box.zstd.ktx2", "mesh": "CornellBox.glb", "node": "cornell_box",
//              "output": "box"}, …]}
//
// Each job's keys are convert's input flags without "--" (bake_input_options(): layout, mesh,
// node, uv-set, placement, page, normals, pages, godot-scene, input-space, allow-mismatch,
// allow-unplaced) plus "input" (required) and "output" (the outputs' name in OUTDIR; default: the
// input's stem). Paths are relative to the job file's folder. Options given on the command line
// apply to every job; a job's own keys replace them.
#pragma once
#include <string>
#include <vector>

#include "bakers/bake_input.h"

namespace ahd {

struct BakeJob {
  BakeInput input;
  std::string output;  // the outputs' name, without folder or extension
};

// Reads the job file. Throws ahd::Error("<path>: <cause>") for malformed JSON, a job without
// input, an unknown key, a value of the wrong type or an empty list. The file is noted in the
// current input record.
std::vector<BakeJob> read_bake_jobs(const std::string& path, const BakeInput& defaults);

}  // namespace ahd

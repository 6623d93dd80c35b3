// Reads a path-traced reference (scripts/truth/bake_truth.py's truth.json + truth.bin).
#pragma once
#include <string>

#include "lab/truth_reference.h"

namespace ahd {

// Reads DIR/truth.json and DIR/truth.bin (or truth.bin.zst: the same bytes, zstd-compressed; the
// script's format, version 1). Throws ahd::Error naming the file on anything malformed; sizes are
// checked against the file before any allocation.
TruthSet load_truth_set(const std::string& dir);

}  // namespace ahd

// NAME.ahd.exr — the lossless intermediate of a conversion: every mip level's SH (as read, with
// coverage and normals) and its fitted AHD (I_z, d, ratio) in float, as a mip-mapped tiled EXR.
// `convert --keep-intermediate` writes it; `transcode` re-quantises it for another profile or
// container without reading the baker files or fitting directions again.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "fit/fit_image.h"

namespace ahd {

constexpr int kIntermediateVersion = 1;

// All levels as the bytes of the intermediate EXR, in memory (the size of the file: for a set,
// convert publishes them with the planes, files/output_set.h). Throws ahd::Error naming `path`.
std::vector<uint8_t> encode_intermediate(const std::string& path, const std::vector<FittedLevel>& levels,
                                         const FitOptions& fit);

// encode_intermediate published alone at `path` (files/output_set.h's publish_file). Throws ahd::Error.
void write_intermediate(const std::string& path, const std::vector<FittedLevel>& levels, const FitOptions& fit);

// Reads and validates (version, channel set, mip chain sizes). Throws ahd::Error("<path>: <cause>").
std::vector<FittedLevel> read_intermediate(const std::string& path, FitOptions* fit);

}  // namespace ahd

// --direction / --ambient-threshold, shared by convert and transcode: whether the direction and
// ratio planes are written (pipeline/convert.h, DirectionPlanes).
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "pipeline/convert.h"

namespace ahd::cli {

struct DirectionArgs {
  std::string mode = "auto";  // auto | keep | drop
  double threshold = kDefaultAmbientThreshold;
};

void add_direction_options(CLI::App* c, DirectionArgs* a);

// Copies the parsed options into `opt`. Throws ahd::Error on a bad value.
void apply_direction_options(const DirectionArgs& a, ConvertOptions* opt);

}  // namespace ahd::cli

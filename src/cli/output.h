// The CLI's edge of a conversion: the terminal summary (where OUT names the files and publishing
// them are the cook's: cook/publish.h).
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "cook/publish.h"
#include "pipeline/run.h"

namespace ahd::cli {

// OutputPaths, output_paths, IntermediateFile, publish_conversion: cook/publish.h.

// The terminal summary of a conversion.
void print_conversion(const std::string& source, const OutputPaths& out, const ConversionRun& run, bool closed_loop,
                      size_t non_finite_inputs);

}  // namespace ahd::cli

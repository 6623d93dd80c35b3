// The options convert and transcode share, parsed once into the library's ConversionOptions
// (<ahd/convert.h>): the CLI adds no defaults or rules of its own.
#pragma once
#include <ahd/convert.h>

#include <CLI/CLI.hpp>
#include <string>

#include "bakers/bake_input.h"

namespace ahd::cli {

struct ConversionArgs {
  ConversionOptions options;  // library defaults, overwritten by the flags
  std::string profile = "uncompressed";  // a name (formats/profiles) or a .json path
  std::string ratio;                     // "" = the profile's
  std::string direction_fit = "refined";
  std::string direction = "auto";
  std::string quality = "default";
  std::string measure = "estimate";      // the CLI prints an error estimate by default
  bool open_loop = false;
  bool strict_ktx = false;
  bool quiet = false;
  std::string container = "ktx2";  // batch conversions into a folder: the container of every output
};

// `fit`: also the options that change the fit (--ratio, --eps, --levels, --coverage-plane), which a
// transcode of a stored fit cannot take.
void add_conversion_options(CLI::App* c, ConversionArgs* a, bool fit);

// The parsed flags as library options (the profile is resolved separately, by name or path).
// Throws ahd::Error on a bad value.
ConversionOptions conversion_options(const ConversionArgs& a);

// The input options (bakers/bake_input.h bake_input_options(): declared there, added here).
void add_input_options(CLI::App* c, BakeInput* a);

}  // namespace ahd::cli

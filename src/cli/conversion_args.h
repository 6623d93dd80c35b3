// The options convert and transcode share, parsed once into the library's ConversionOptions
// (<ahd/convert.h>): one flag per row of the option table (api/option_table.h), which also holds
// the one default the command has of its own (--measure estimate: the command prints an error
// estimate, the library measures nothing unless asked).
#pragma once
#include <ahd/convert.h>

#include <CLI/CLI.hpp>
#include <map>
#include <string>

#include "bakers/bake_input.h"

namespace ahd::cli {

struct ConversionArgs {
  ConversionOptions options;  // library defaults; the flags of text, number and boolean options write here
  std::map<std::string, std::string> enums;  // an enumerated option's flag value, by option name
  std::map<std::string, bool> negated;       // a flag that sets a boolean option false was given, by option name
  bool quiet = false;
  std::string container = "ktx2";  // batch conversions into a folder: the container of every output
};

// `fit`: also the options that change the fit (--ratio, --eps, --direction-fit, --levels,
// --coverage-plane), which a transcode of a stored fit cannot take.
void add_conversion_options(CLI::App* c, ConversionArgs* a, bool fit);

// The parsed flags as library options (the profile is resolved separately, by name or path).
// Throws ahd::Error on a bad value.
ConversionOptions conversion_options(const ConversionArgs& a);

// The input options (bakers/bake_input.h bake_input_options(): declared there, added here).
void add_input_options(CLI::App* c, BakeInput* a);

}  // namespace ahd::cli

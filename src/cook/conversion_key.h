// The key of a conversion (`convert --print-key`, `convert --cache`): SHA-256 over everything that
// decides its output bytes — and nothing else, so that a cache is shared between checkouts,
// machines and thread counts:
//   - a format line (bump kKeyFormat when what the key covers changes) and the tool version;
//   - every option that changes the outputs (ConversionOptions minus threads/progress/cancel, the
//     input options of bakers/bake_input.h, the built-in sample's size/order/seed);
//   - the output's stem and container (they are in the file names and the manifest);
//   - every file the conversion read (files/input_record.h: the baker's images, .exr.import, .lmbake,
//     project.godot, meshes and their buffers, placements, the profile and layout preset files),
//     in the order read, by content (size and SHA-256 over 4 MiB chunks), not by path.
// Paths are not in the key: the report's "source" line and seconds are those of the run that filled
// a cache entry (the manifest and planes never name a path).
#pragma once
#include <ahd/convert.h>

#include <string>

#include "bakers/bake_input.h"
#include "files/input_record.h"

namespace ahd {

// Raise when the fields below, or the bytes the same inputs give, change without a version bump.
inline constexpr int kKeyFormat = 3;  // 3: refined d per texel (issue 43); 2: manifests list instances; plain maps keep their scale

// The text the key hashes, one "field value" per line: conversion_options_text, then
// input_files_text of the files read. Reads every recorded file again to hash it; throws
// ahd::Error naming a file that can no longer be read.
std::string conversion_key_text(const BakeInput& in, const ConversionOptions& o, const std::string& out_name,
                                const InputRecord& record);
std::string conversion_options_text(const BakeInput& in, const ConversionOptions& o, const std::string& out_name);
std::string input_files_text(const std::vector<std::string>& files);

// The key of the command itself, before anything is read (`--cache`'s direct lookup): the options
// as given, the input's path as given, the working directory and the data-file folder. The cache
// maps it to what the last such run read and probed (cook/conversion_cache.h InputsRecord); when every
// probe still holds, hashing those files gives the conversion key without reading the images.
std::string command_key(const BakeInput& given, const ConversionOptions& o, const std::string& out_name,
                        const std::string& profile_arg);

// sha256 of conversion_key_text: 64 lower-case hex digits.
std::string conversion_key(const std::string& key_text);

}  // namespace ahd

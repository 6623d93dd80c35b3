// The public options (<ahd/convert.h>) resolved into what the pipeline stages take. One place, so
// the CLI and the library agree on every default and every check.
#pragma once
#include <ahd/convert.h>

#include "pipeline/convert.h"
#include "pipeline/package.h"
#include "pipeline/profile.h"

namespace ahd {

struct ResolvedOptions {
  Profile profile;
  PipelineOptions convert;
  PackageOptions package;
};

// Checks every option (throws ahd::Error naming the option) and resolves the profile: a built-in one
// by name, or `profile_json`. `name` is the output stem.
ResolvedOptions resolve_options(const ConversionOptions& o, const std::string& name);

// The same with a profile the caller already loaded (the CLI finds profiles on disk by name).
ResolvedOptions resolve_options(const ConversionOptions& o, const std::string& name, const Profile& profile);

// Throws ahd::Error unless `sh` is a consistent image: positive size, 1, 4 or 9 coefficients, and
// data/coverage/normals of exactly the sizes the size implies.
void check_sh_image(const ShImage& sh);

}  // namespace ahd

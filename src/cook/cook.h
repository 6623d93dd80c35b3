// The cook sequence (<ahd/cook.h> cook()): direct cache lookup → read the bake → key → cache hit, or
// convert → publish → depfile → store. `ahdpack convert` runs it through cook_conversion below,
// which adds the one thing the public call leaves out: the pipeline's full result, for the
// command's terminal summary.
#pragma once
#include <ahd/cook.h>

#include <functional>

#include "cook/publish.h"
#include "pipeline/run.h"

namespace ahd {

// What the terminal summary of a conversion needs (called once the set is published and the
// depfile written, before the cache store; not for hits).
struct CookConverted {
  const std::string& source;
  const OutputPaths& out;
  const ConversionRun& run;
  bool closed_loop;
  size_t non_finite_texels;
};

struct CookHooks {
  CookEvents events;
  std::function<void(const CookConverted&)> converted;
};

// cook() with `hooks`. Same contract.
CookResult cook_conversion(const CookRequest& request, const CookHooks& hooks);

}  // namespace ahd

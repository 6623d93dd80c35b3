// What the command takes from the environment (the library reads none).
#pragma once

namespace ahd::cli {

// AHDPACK_MAX_SIZE (a whole number ≥ 1): the largest width/height of an image or texture level the
// readers accept (containers/limits.h). A malformed value keeps the default: it must never silently
// lift the limit.
void apply_size_limit_from_environment();

}  // namespace ahd::cli

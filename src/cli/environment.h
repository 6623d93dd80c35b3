// What the command takes from the environment (the library reads none).
#pragma once

namespace ahd::cli {

// AHDPACK_MAX_SIZE (a whole number ≥ 1): the largest width/height of an image or texture level the
// readers accept (containers/limits.h). A malformed value (not digits, 0, over 2^32-1) throws
// ahd::Error: it must neither silently lift the limit nor be silently ignored.
void apply_size_limit_from_environment();

}  // namespace ahd::cli

// What the command takes from the environment (the library reads none).
#pragma once

namespace ahd::cli {

// AHDPACK_MAX_SIZE (a whole number ≥ 1): the largest width/height of an image or texture level the
// readers accept (containers/limits.h). A malformed value (not digits, 0, over 2^32-1) throws
// ahd::Error: it must neither silently lift the limit nor be silently ignored.
void apply_size_limit_from_environment();

// AHD_CPU_DISABLE (a whole number, a mask of ahd::cpu::Feature): a test hook, not a user setting.
// The instruction-set extensions of the mask are treated as absent (ahd::cpu::disable_for_tests),
// so scripts/platform-cli-bytes.sh can run the CLI down each SIMD path and compare the bytes
// (they never differ; only the speed does). Unset or empty: nothing is disabled. A malformed value
// throws ahd::Error.
void apply_cpu_disable_from_environment();

}  // namespace ahd::cli

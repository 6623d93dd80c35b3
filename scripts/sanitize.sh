#!/usr/bin/env bash
# The whole unit-test suite built with AddressSanitizer + UndefinedBehaviorSanitizer (clang 14)
# into build-asan/, then run with ctest. The same build also holds the libFuzzer targets (fuzz/):
# everything is compiled with -fsanitize=fuzzer-no-link too, so one instrumented library serves
# both (scripts/fuzz.sh runs them). Built: the unit and integration tests (AHD_TEST_KINDS); left
# out: the judges (tests/judges: Mesa's llvmpipe, whose JIT under ASan is impractically slow, the
# browsers and Godot — not our code) and the accuracy sweeps (tests/accuracy: thousands of inputs
# through code the unit tests run instrumented); the bench.
# The test sources at -O0 (AHD_TEST_OPT_FLAGS): half the instrumented compile time of -Og
# (godot_array_mesh_test.cpp 20.9 s -> 10.7 s); the library keeps -O1.
# -gline-tables-only: the reports' stack traces name files and lines (all they print) without the
# full debug info (cmd_convert.cpp: 28.4 → 24.1 s of clang -O1 with both sanitizers).
# AHD_WERROR=ON (.ci/run) makes warnings errors (clang-14, everything including the fuzz targets).
# Usage: bash scripts/sanitize.sh [--build-only]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -fsanitize=fuzzer-no-link"
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 "${launcher[@]}" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only $SAN" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only $SAN" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DAHD_TEST_OPT_FLAGS=-O0 -DAHD_BUILD_BENCH=OFF -DAHD_TEST_KINDS="unit;integration" -DAHD_FUZZ=ON -DAHD_WARNINGS_AS_ERRORS="${AHD_WERROR:-OFF}" >/dev/null
cmake --build build-asan -j "$(nproc)"
[ "${1:-}" = "--build-only" ] && exit 0
# Leaks are errors; the suppressions name third-party libraries' own one-time allocations only.
# intercept_tls_get_addr=0: LeakSanitizer's tracking of dynamic TLS (what dlopen'd libraries'
# threads hold) reads a stale block on Debian 12's glibc once a module's threads have exited, and
# its tracer dies with SIGSEGV at exit ("DTLS 13 at 0x1f2e-0x800003030", then "LeakSanitizer has
# encountered a fatal error"): `preview` after OpenImageIO's module wrote its PNGs, every run
# of OutputFaults.PreviewOfADeeplyNestedReportIsOneErrorLine, never from a shell. Dynamic TLS is
# then not scanned as a root; static TLS, stacks and globals still are.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:intercept_tls_get_addr=0"
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Label `nosan` (tests/labels.cmake) leaves out: the consumer test, which installs the package and
# builds a program with the default compiler (not an instrumented build's job); the preview page
# test (PreviewChromium.*) and the three.js render test (ThreeRender.*, convert + a browser), which
# run a browser, not our code (Preview3d.* stays: it runs the 3D view's writer,
# src/cli/preview_3d.cpp); and three accuracy measurements run only in the normal suite: they repeat
# code the instrumented suite already runs (BC6H `max` on the hard 8×8 and gradient inputs, BC6H
# `default` and `fast` on every codec test, the closed-form fit on every fit test) on thousands
# more inputs (the BC6H pair took 2 of its 7 minutes of tests, the shared images' error 27 s more).
# Label `slow` is left out too: the long integration runs (real bakes through the whole CLI, kills at
# every rename, the four-page atlas) repeat under the sanitizers what their small siblings already
# run instrumented, at 3-5x the time; the normal suite runs them (.ci/run's first step).
# Label `accuracy` too: sweeps over thousands of inputs of code the unit tests run instrumented.
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -LE "nosan|slow|accuracy"

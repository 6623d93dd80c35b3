#!/usr/bin/env bash
# Configures and builds ahdpack (Release) into build/. Used by run-sample.sh and test.sh.
# AHD_WERROR=ON makes warnings errors (.ci/run sets it: the gcc build is warning-free); off by default
# so that a user's other compiler version with new warnings still builds.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_WARNINGS_AS_ERRORS="${AHD_WERROR:-OFF}" >/dev/null
cmake --build build -j "$(nproc)"

#!/usr/bin/env bash
# Configures and builds ahdpack (Release) into build/. Used by run-sample.sh and test.sh.
# Warnings are errors (the CI's gcc build: a full build is warning-free); AHD_WERROR=OFF builds with
# a compiler whose new warnings should not stop you.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_WARNINGS_AS_ERRORS="${AHD_WERROR:-ON}" >/dev/null
cmake --build build -j "$(nproc)"

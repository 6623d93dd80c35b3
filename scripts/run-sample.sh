#!/usr/bin/env bash
# README command 1: install what is missing, build, and convert the built-in sample lightmap.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/ahdpack convert -o ahdpack-out/sample.ktx2 "$@"

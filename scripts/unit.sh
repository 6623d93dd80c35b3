#!/usr/bin/env bash
# The quick loop: every test labelled `unit` of tests/unit (tests/labels.cmake) in ONE gtest process, plus the
# documentation citation check. `ctest -L unit` runs the same tests one process each, and every
# process of a binary linking OpenImageIO pays ≈ 0.25 s CPU to start (Debian's OpenImageIO loads
# ≈ 260 shared libraries; the dynamic loader's symbol lookups are three quarters of it).
# Usage: bash scripts/unit.sh [BUILD_DIR]   (default build/, configured by scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake --build "$build" --target ahd_unit_tests >/dev/null
python3 tests/check_doc_citations.py . >/dev/null || { python3 tests/check_doc_citations.py .; exit 1; }
# The binary of tests/unit, less the few tests of another kind its files still hold (labels.cmake).
filter=$(ctest --test-dir "$build" -N -L unit | sed -n 's/^ *Test *#[0-9]*: //p' | grep -v '^\(Docs\|Layering\)\.' | paste -sd: -)
exec "$build/tests/ahd_unit_tests" --gtest_filter="$filter" --gtest_brief=1

#!/usr/bin/env bash
# Process start and EXR read: ahdpack (--help; convert's own read stage), OpenImageIO's oiiotool,
# and bench/probes/exr_read.cpp (a process linking OpenEXR only), each three times, on one file.
# Usage: bash scripts/probe-exr-read.sh [FILE.exr]   (default: the 2048² ragdoll bake)
# Needs a built ./build. Builds build/probes/exr_read. docs/performance-real.md has a run.
set -euo pipefail
cd "$(dirname "$0")/.."
f="${1:-../shared/data/bakes/godot-ragdoll-plain/ragdoll_physics.exr}"
mkdir -p build/probes
[ build/probes/exr_read -nt bench/probes/exr_read.cpp ] ||
  g++ -std=c++20 -O2 bench/probes/exr_read.cpp -I/usr/include/OpenEXR -I/usr/include/Imath -lOpenEXR-3_1 -lIex-3_1 \
    -lIlmThread-3_1 -lImath-3_1 -o build/probes/exr_read
t() { /usr/bin/time -f "  %e s wall, %U s user, %S s sys, %M KB max RSS" "$@"; }
echo "load $(cut -d' ' -f1-3 /proc/loadavg); libraries: ahdpack $(ldd build/ahdpack | wc -l), exr_read $(ldd build/probes/exr_read | wc -l)"
for i in 1 2 3; do
  echo "ahdpack --help";        t build/ahdpack --help > /dev/null
  echo "exr_read $f";           t build/probes/exr_read "$f"
  echo "oiiotool $f";           t oiiotool "$f" --printstats -o /dev/null > /dev/null 2>&1 || t oiiotool --stats "$f" > /dev/null
done

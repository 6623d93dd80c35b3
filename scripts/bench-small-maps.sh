#!/usr/bin/env bash
# Issue 45's small maps: each one converted by a whole `ahdpack convert` process (start included)
# against OpenImageIO's read of the same file (docs/performance-real.md "Small maps, whole
# processes"). Plain maps: the real Godot plain bake (tests/data/bakes/godot-ragdoll-plain) resized
# by oiiotool to 256², 512², 1024² (half, PIZ, as Godot writes them); L1 and L2: `bench convert`'s
# generated inputs at 256² and 1024². One `ahdpack bench convert` run prints every figure: its
# "whole process" lines are the medians of --process-runs processes (CPU from wait4).
# Usage: bash scripts/bench-small-maps.sh [BUILD_DIR] [PROCESS_RUNS]   (default build/, 5)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
runs=${2:-5}
ahdpack=$build/ahdpack
src=tests/data/bakes/godot-ragdoll-plain/ragdoll_physics.exr
command -v oiiotool >/dev/null || { echo "bench-small-maps: oiiotool (OpenImageIO's tools) is needed" >&2; exit 1; }
[ -x "$ahdpack" ] || { echo "bench-small-maps: no $ahdpack (build it first)" >&2; exit 1; }
work=$(mktemp -d /tmp/ahd-small-maps.XXXXXX)
trap 'rm -rf "$work"' EXIT
plain=()
for s in 256 512 1024; do
  oiiotool "$src" --resize ${s}x${s} -d half --compression piz -o "$work/plain$s.exr"
  plain+=(--plain-file "$work/plain$s.exr")
done
"$ahdpack" bench convert --sizes 256 1024 --l1 256 1024 --plain 0 "${plain[@]}" --process-runs "$runs" --dir "$work/bench"

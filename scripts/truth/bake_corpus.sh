#!/usr/bin/env bash
# Bakes the path-traced truth corpus (docs/accuracy-real-lighting.md "The corpus") into
# tests/data/truth/<name>/ with Blender Cycles: scripts/truth/bake_truth.py per scene, then
# truth.bin compressed with zstd where it passes 2 MB (report truth reads either).
#
#   apt-get install blender python3-numpy zstd
#   bash scripts/truth/bake_corpus.sh                # every scene below
#   ONLY="lamps emissive" bash scripts/truth/bake_corpus.sh   # some of them
#
# name            scene         size  samples  role      (margin: the UV charts' gutters, default 0.04)
#   area          area            64      128  tuned (the fit's choices were made on it)
#   sun           sun             64      128  tuned
#   cornell_area  cornell_area   128      256  held out
#   cornell_sun   cornell_sun     96     1024  held out
#   lamps         lamps           64     1024  held out
#   emissive      emissive        64       16  held out
#   cornell_sun_256 cornell_sun  256       32  held out
#   lamps_256     lamps          256       16  held out
#   cornell_tight cornell_area    64      256  held out  charts packed tight (margin 0.002)
set -euo pipefail
cd "$(dirname "$0")/../.."
corpus=(
  "area area 64 128"
  "sun sun 64 128"
  "cornell_area cornell_area 128 256"
  "cornell_sun cornell_sun 96 1024"
  "lamps lamps 64 1024"
  "emissive emissive 64 16"
  "cornell_sun_256 cornell_sun 256 32"
  "lamps_256 lamps 256 16"
  "cornell_tight cornell_area 64 256 0.002"
)
for entry in "${corpus[@]}"; do
  set -- $entry
  name=$1 scene=$2 size=$3 samples=$4 margin=${5:-0.04}
  if [ -n "${ONLY:-}" ] && [[ " $ONLY " != *" $name "* ]]; then continue; fi
  out=tests/data/truth/$name
  glb=()
  case $name in area | sun) glb=(--glb "$out/$name.glb") ;; esac  # the scenes as glTF, for a look
  blender -b --python scripts/truth/bake_truth.py -- --scene "$scene" --out "$out" --size "$size" \
    --samples "$samples" --margin "$margin" "${glb[@]}" > "/tmp/bake_truth_$name.log" 2>&1 || { echo "bake_corpus: $name failed (/tmp/bake_truth_$name.log)" >&2; exit 1; }
  rm -f "$out/truth.bin.zst"
  if [ "$(stat -c %s "$out/truth.bin")" -gt 2000000 ]; then
    zstd -19 -q --rm "$out/truth.bin" -o "$out/truth.bin.zst"
  fi
  echo "bake_corpus: $out"
done

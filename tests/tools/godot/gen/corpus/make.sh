#!/usr/bin/env bash
# Regenerates tests/data/godot/corpus/: Godot 4.6 (its official web build, run_godot.mjs) writes each
# project's scene, meshes and .lmbake and hands back every lightmap user's world-space arrays;
# bake.mjs lays the projects out and writes their lightmap EXRs (README.md beside this file).
#   bash tests/tools/godot/gen/corpus/make.sh [OUTDIR]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../../../.." && pwd)"
out="${1:-$repo/tests/data/godot/corpus}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# The FBX files of the fbx projects, packed as res://fbx/NAME.fbx.
fbx=()
for f in room.fbx room_zup.fbx tiles.fbx; do fbx+=(--add "$repo/tests/data/godot/handmade/$f=fbx/$f"); done
node "$here/../../run_godot.mjs" --project "$here" --out "$tmp" --timeout 180 "${fbx[@]}"
node "$here/../../f32_json.mjs" "$tmp/corpus.json" "$tmp/wild.json"
mkdir -p "$out"
node "$here/bake.mjs" "$tmp" "$out"
# Godot's own world-space arrays of every lightmap user, for the readers' tests.
cp "$tmp/corpus.json" "$out/godot_arrays.json"
echo "corpus: $(du -sk "$out" | cut -f1) KiB -> $out"

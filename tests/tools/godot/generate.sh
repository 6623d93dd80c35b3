#!/usr/bin/env bash
# Regenerates tests/data/godot/generated/ with Godot 4.6 itself (its official web build, run in
# headless Chromium by run_godot.mjs; see README.md beside this file). ~15 s and ~1 GB per generator.
#   bash tests/tools/godot/generate.sh [OUTDIR]
# Every file in OUTDIR is replaced; the JSON files go through f32_json.mjs.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
out="${1:-$repo/tests/data/godot/generated}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

run() {  # run NAME [run_godot.mjs options...]
  local name="$1"; shift
  echo "generate: $name"
  node "$here/run_godot.mjs" --project "$here/gen/$name" --out "$tmp/out" --timeout 180 "$@"
}

run primitives
run arraymesh
# The real bakes' .lmbake files, packed under res://real/<path below tests/data>.
adds=()
while IFS= read -r f; do
  adds+=(--add "$f=real/${f#"$repo/tests/data/"}")
done < <(find "$repo/tests/data" -name '*.lmbake' -not -path '*/godot/generated/*' -not -path '*/godot/corpus/*' | sort)
run lmbake "${adds[@]}"

node "$here/f32_json.mjs" "$tmp"/out/*.json
mkdir -p "$out"
find "$out" -maxdepth 1 -type f ! -name README.md -delete
cp "$tmp"/out/* "$out"/
echo "generate: $(ls "$tmp/out" | wc -l) files, $(du -sk "$out" | cut -f1) KiB -> $out"

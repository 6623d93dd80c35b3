#!/usr/bin/env bash
# The cook test: install ahdpack from BUILD into a temporary prefix (as tests/consumer/run.sh), build
# this folder's project with Ninja over the lightmaps in INPUT_DIR (a.exr, b.exr, world.exr + its
# Godot files, written by CookTest.CmakeNinjaCooksOnlyWhatChanged), then check: the first build cooks
# three, a second has nothing to do, touching world.exr.import (then a.exr) cooks only that one,
# and every output but the report equals a direct `ahdpack convert`.
# Usage: run.sh BUILD_DIR AHDPACK_EXE INPUT_DIR
set -euo pipefail
build="$1"; cli="$2"; in="$3"; here="$(cd "$(dirname "$0")" && pwd)"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cmake -S "$here" -B "$tmp/build" -G Ninja -DCMAKE_PREFIX_PATH="$tmp/prefix" -DINPUT_DIR="$in" >/dev/null
cooked() { grep -o "ahdpack: cooking [a-z]*" "$1" | sed 's/.* //' | sort | tr '\n' ' '; }
up_to_date() {
  ninja -C "$tmp/build" -n > "$tmp/n.log"
  grep -q "no work to do" "$tmp/n.log" || { echo "FAIL: $1: the build is not up to date:"; cat "$tmp/n.log"; exit 1; }
}

cmake --build "$tmp/build" > "$tmp/1.log"
echo "first build cooked: $(cooked "$tmp/1.log")"
[ "$(cooked "$tmp/1.log")" = "a b world " ] || { echo "FAIL: first build"; cat "$tmp/1.log"; exit 1; }
grep -q "world.exr.import" "$tmp/build/lm/world.d" || { echo "FAIL: world.d does not name world.exr.import"; exit 1; }
up_to_date "second build"
echo "second build: no work to do"

sleep 1  # a coarse file-system clock must see the touch as newer than the outputs
touch "$in/world.exr.import"
cmake --build "$tmp/build" > "$tmp/2.log"
echo "after touching world.exr.import cooked: $(cooked "$tmp/2.log")"
[ "$(cooked "$tmp/2.log")" = "world " ] || { echo "FAIL: touch world.exr.import"; cat "$tmp/2.log"; exit 1; }
up_to_date "after world"
touch "$in/a.exr"
cmake --build "$tmp/build" > "$tmp/3.log"
echo "after touching a.exr cooked: $(cooked "$tmp/3.log")"
[ "$(cooked "$tmp/3.log")" = "a " ] || { echo "FAIL: touch a.exr"; cat "$tmp/3.log"; exit 1; }
up_to_date "after a"

mkdir -p "$tmp/direct"
"$cli" convert "$in/a.exr" -o "$tmp/direct/a.ktx2" --profile pc-bc -q
"$cli" convert "$in/b.exr" -o "$tmp/direct/b.ktx2" --profile pc-bc -q
"$cli" convert "$in/world.exr" -o "$tmp/direct/world.ktx2" --profile pc-bc --normals "$in/n.exr" -q
n=0
for f in "$tmp/direct"/*; do
  name="$(basename "$f")"
  [[ "$name" == *.report.json ]] && continue
  cmp "$f" "$tmp/build/lm/$name"
  n=$((n + 1))
done
[ "$n" -ge 9 ] || { echo "FAIL: only $n files compared"; exit 1; }
echo "outputs: $n files identical to a direct ahdpack convert"

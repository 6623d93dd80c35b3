#!/usr/bin/env bash
# Consumer.InstalledBakersMatchCli: install ahdpack from BUILD into a temporary prefix, build this
# folder against it, and cook through the installed ahdpack::cook and ahdpack::bakers (ahd::cook;
# ahd::read_bake + ahd::convert) what `ahdpack convert` converts: the vermilion Godot project's
# lightmap (its scene found in the project: meshes, placement, normals; README of
# tests/data/bakes) and a Bakery SH set (make_bakery_set.py) with a mesh. Every file but the
# report (its seconds differ) must be the CLI's bytes, and so must the depfile and the cache key;
# a cache filled by the library serves the CLI.
# Usage: bakers.sh BUILD_DIR AHDPACK_EXE SOURCE_DIR
set -euo pipefail
build="$1"; cli="$2"; src="$3"; here="$(cd "$(dirname "$0")" && pwd)"
command -v python3 >/dev/null || { echo "skipped: python3 not found (it writes the Bakery set)"; exit 77; }
vermilion="$src/tests/data/bakes/godot42-vermilion/project/scenes/world.exr"
[ -f "$vermilion" ] || { echo "skipped: $vermilion not found"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
# The installed command: it and the libraries read the same installed formats/ (the depfiles name
# the profile file they read).
cli="$tmp/prefix/bin/ahdpack"
[ -x "$cli" ] || { echo "FAIL: no installed ahdpack (the CLI built: $2)"; exit 1; }
cmake -S "$here" -B "$tmp/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/build" --target consumer_bakers >/dev/null
con="$tmp/build/consumer_bakers"
# The libraries carry their file-format dependencies: a cook links none of them itself.
link="$(awk '/^build consumer_bakers:/ {f = 1} f && /LINK_LIBRARIES = / {print; exit}' "$tmp/build/build.ninja")"
echo "$link" | grep -q "libahd_cook\.so" || { echo "FAIL: consumer_bakers does not link libahd_cook.so: $link"; exit 1; }
if echo "$link" | grep -qi "OpenImageIO\|assimp\|OpenEXR\|OpenColorIO"; then
  echo "FAIL: a consumer of ahdpack::cook links a file-format library: $link"; exit 1
fi
unset AHD_FORMATS_DIR  # the library finds the installed formats beside itself

# same_set CLI_DIR LIB_DIR: the same file names, and every file but the report the same bytes.
same_set() {
  diff <(ls "$1") <(ls "$2") >&2 || { echo "FAIL: $1 and $2 hold different files" >&2; exit 1; }
  local n=0 f name
  for f in "$1"/*; do
    name="$(basename "$f")"
    [[ "$name" == *.report.json ]] && continue
    cmp "$f" "$2/$name" >&2 || { echo "FAIL: $name differs ($1 vs $2)" >&2; exit 1; }
    n=$((n + 1))
  done
  [ "$n" -ge 3 ] || { echo "FAIL: only $n files compared in $1" >&2; exit 1; }
  echo "$n"
}

# check NAME IN STEM [input options…]: CLI and ahd::cook in two folders with the same relative
# outputs (the depfile names its target as given), the key, ahd::read_bake + ahd::convert, a cache.
check() {
  local what="$1" in="$2" stem="$3"; shift 3
  mkdir -p "$tmp/$what"/{cli,cook,read}
  (cd "$tmp/$what/cli" && "$cli" convert "$in" "$@" -o "out/$stem.ktx2" --depfile "out/$stem.d" -q)
  (cd "$tmp/$what/cook" && "$con" cook "$in" "out/$stem.ktx2" "$@" --depfile "out/$stem.d" >/dev/null)
  local n; n="$(same_set "$tmp/$what/cli/out" "$tmp/$what/cook/out")"
  local k_cli k_lib
  k_cli="$(cd "$tmp/$what/cli" && "$cli" convert "$in" "$@" -o "out/$stem.ktx2" --print-key)"
  k_lib="$(cd "$tmp/$what/cook" && "$con" key "$in" "out/$stem.ktx2" "$@" | sed -n 's/^key //p')"
  [ -n "$k_cli" ] && [ "$k_cli" = "$k_lib" ] || { echo "FAIL: $what: key $k_lib, the CLI's $k_cli"; exit 1; }
  # ahd::read_bake + ahd::convert: the same planes and manifest (its report has no "source").
  "$con" read "$in" "$tmp/$what/read" "$stem" "$@" >/dev/null
  local p=0 f
  for f in "$tmp/$what/read"/*; do
    [[ "$f" == *.report.json ]] && continue
    cmp "$f" "$tmp/$what/cli/out/$(basename "$f")" || { echo "FAIL: $what: read_bake + convert: $(basename "$f") differs"; exit 1; }
    p=$((p + 1))
  done
  [ "$p" -ge 2 ] || { echo "FAIL: $what: only $p files from read_bake + convert"; exit 1; }
  # The manifest compared above lists the placed scene's instances when the input has a scene
  # (BakeRead::instances handed to ahd::convert; docs/container-format.md "Instances").
  if [ "$what" = vermilion ] && ! grep -q '"instances"' "$tmp/$what/read/$stem.json"; then
    echo "FAIL: $what: read_bake + convert wrote no instances"; exit 1
  fi
  # A cache filled through the library serves the CLI (same key, same entry format).
  (cd "$tmp/$what/cook" && "$con" cook "$in" "cached/$stem.ktx2" "$@" --cache "$tmp/$what/cache" >/dev/null)
  local hit
  hit="$(cd "$tmp/$what/cli" && "$cli" convert "$in" "$@" -o "cached/$stem.ktx2" --cache "$tmp/$what/cache")"
  echo "$hit" | grep -q "^cache hit $k_cli " || { echo "FAIL: $what: the CLI missed the library's cache entry: $hit"; exit 1; }
  same_set "$tmp/$what/cli/cached" "$tmp/$what/cook/cached" >/dev/null
  echo "$what: $n files identical (planes, manifest, depfile), key $k_cli, $p from read_bake + convert, cache shared"
}

check vermilion "$vermilion" world --profile pc-bc
python3 "$here/make_bakery_set.py" "$tmp/bakery-set"
check bakery "$tmp/bakery-set/Scene_LM0_L0.hdr" scene --mesh "$tmp/bakery-set/quad.obj"

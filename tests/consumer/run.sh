#!/usr/bin/env bash
# The consumer test: install ahdpack from BUILD into a temporary prefix, build this folder against it
# with find_package(ahdpack), convert the built-in sample in memory (C++ and C) and compare every
# file but the report (its seconds differ) with what `ahdpack convert` writes.
# Usage: run.sh BUILD_DIR AHDPACK_EXE
set -euo pipefail
build="$1"; cli="$2"; here="$(cd "$(dirname "$0")" && pwd)"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cmake -S "$here" -B "$tmp/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/build" >/dev/null
# ahd_io must not be needed by a program that only converts: check the link lines.
grep -q "LINK_LIBRARIES = .*libahd\.a" "$tmp/build/build.ninja" || { echo "FAIL: no link line found"; exit 1; }
if grep -E "LINK_LIBRARIES = " "$tmp/build/build.ninja" | grep -qi "OpenImageIO\|assimp"; then
  echo "FAIL: a consumer of ahdpack::ahd links OpenImageIO or Assimp"; exit 1
fi
for profile in uncompressed pc-bc; do
  mkdir -p "$tmp/$profile"/{cli,cpp,c}
  "$cli" convert -o "$tmp/$profile/cli/sample.ktx2" --profile "$profile" -q
  "$tmp/build/consumer_cpp" "$tmp/$profile/cpp" "$profile"
  "$tmp/build/consumer_c" "$tmp/$profile/c" "$profile"
  n=0
  for f in "$tmp/$profile"/cli/*; do
    name="$(basename "$f")"
    [[ "$name" == *.report.json ]] && continue
    cmp "$f" "$tmp/$profile/cpp/$name"
    cmp "$f" "$tmp/$profile/c/$name"
    n=$((n + 1))
  done
  [ "$n" -ge 4 ] || { echo "FAIL: only $n files compared for $profile"; exit 1; }
  echo "$profile: $n files identical (CLI, C++ API, C API)"
done

#!/usr/bin/env bash
# The consumer test: install ahdpack from BUILD into a temporary prefix, build this folder against it
# with find_package(ahdpack), convert the built-in sample in memory (C++ and C) and compare every
# file but the report (its seconds differ) with what `ahdpack convert` writes.
# Usage: run.sh BUILD_DIR AHDPACK_EXE
set -euo pipefail
build="$1"; cli="$2"; here="$(cd "$(dirname "$0")" && pwd)"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
# Layering: no symbol that lab or sample code defines (strong: T/D/B/R) is defined in, or needed by,
# the installed libahd (static and shared); the lab itself is not installed.
nm -g --defined-only "$build/libahd_lab.a" "$build/libahd_sample.a" 2>/dev/null | awk 'NF == 3 && $2 ~ /^[TDBR]$/ {print $3}' \
  | sort -u > "$tmp/lab.syms"
[ -s "$tmp/lab.syms" ] || { echo "FAIL: no lab/sample symbols read from $build"; exit 1; }
if find "$tmp/prefix" -name 'libahd_lab*' | grep -q .; then echo "FAIL: the lab is installed"; exit 1; fi
n_libs=0
for lib in $(find "$tmp/prefix" -name 'libahd.a' -o -name 'libahd.so*' -type f); do
  for kind in defined undefined; do
    bad="$(nm -g $([ "${lib%.a}" = "$lib" ] && echo -D) --$kind-only "$lib" 2>/dev/null | awk '{print $NF}' | sort -u \
      | comm -12 - "$tmp/lab.syms")"
    [ -z "$bad" ] || { echo "FAIL: $lib has $kind lab/sample symbols:"; echo "$bad" | c++filt | head; exit 1; }
  done
  n_libs=$((n_libs + 1))
done
[ "$n_libs" -ge 1 ] || { echo "FAIL: no installed libahd found"; exit 1; }
echo "layering: $n_libs installed libahd, no symbol of the lab or the sample ($(wc -l < "$tmp/lab.syms") checked)"
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

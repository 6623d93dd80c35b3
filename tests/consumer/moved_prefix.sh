#!/usr/bin/env bash
# The installed command away from the source tree: install ahdpack from BUILD into a temporary
# prefix, copy the prefix to another folder and delete the original, then run the copy's ahdpack
# under strace. It must find its data in <copy>/share/ahdpack/formats (the profile and the baker
# layout the conversions name, the layout list) and open nothing under the source tree — whose
# formats/ path is compiled in as the build tree's fallback — nor under BUILD or the deleted prefix;
# its conversions must equal the build tree's byte for byte (the report aside: its seconds differ).
# Usage: moved_prefix.sh BUILD_DIR AHDPACK_EXE. Exit 77 (ctest SKIP_RETURN_CODE) without strace.
set -euo pipefail
build="$(cd "$1" && pwd)"; cli="$2"; src="$(cd "$(dirname "$0")/../.." && pwd)"
command -v strace >/dev/null 2>&1 || { echo "skipped: strace not found (scripts/setup.sh installs it)"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cp -a "$tmp/prefix" "$tmp/moved"
rm -rf "$tmp/prefix"
exe="$tmp/moved/bin/ahdpack"
# The test means something only while the fallback is compiled in: the binary names $src/formats.
grep -qaF "$src/formats" "$exe" || { echo "FAIL: $exe does not name $src/formats (test premise gone)"; exit 1; }
unset AHD_FORMATS_DIR AHD_THREE_DIR
"$cli" sample -o "$tmp/in.exr" --size 64
trace() { strace -f -qq -e trace=%file -o "$tmp/strace.$1.txt" "${@:2}"; }
mkdir -p "$tmp/out-moved" "$tmp/out-build"
(cd "$tmp" && trace layouts "$exe" layouts > "$tmp/layouts.txt")
(cd "$tmp" && trace sample "$exe" convert -q -o "$tmp/out-moved/sample.ktx2" --profile pc-bc)
(cd "$tmp" && trace canonical "$exe" convert -q -o "$tmp/out-moved/in.ktx2" --profile pc-bc --layout canonical in.exr)
"$cli" convert -q -o "$tmp/out-build/sample.ktx2" --profile pc-bc
(cd "$tmp" && "$cli" convert -q -o "$tmp/out-build/in.ktx2" --profile pc-bc --layout canonical in.exr)
cat "$tmp"/strace.*.txt > "$tmp/strace.txt"
for dir in "$src" "$build" "$tmp/prefix"; do
  if grep -F "\"$dir/" "$tmp/strace.txt" | grep -q .; then
    echo "FAIL: the moved install touched $dir:"; grep -F "\"$dir/" "$tmp/strace.txt" | head -5; exit 1
  fi
done
for f in bakers/canonical.json profiles/pc-bc.json; do
  grep -qF "\"$tmp/moved/share/ahdpack/formats/$f\"" "$tmp/strace.txt" || { echo "FAIL: the moved install did not read its $f"; exit 1; }
done
n_layouts="$(ls "$src/formats/bakers" | grep -c '\.json$')"
for name in $(ls "$src/formats/bakers" | sed -n 's/\.json$//p'); do
  grep -qw -- "$name" "$tmp/layouts.txt" || { echo "FAIL: the moved install does not list layout $name"; exit 1; }
done
n=0
for f in "$tmp/out-build"/*; do
  [[ "$f" == *.report.json ]] && continue
  cmp "$f" "$tmp/out-moved/$(basename "$f")"; n=$((n + 1))
done
[ "$n" -ge 8 ] || { echo "FAIL: only $n files compared"; exit 1; }
echo "moved prefix: $n_layouts layouts listed, its own formats/ read, nothing opened under the source or build tree;" \
  "$n files identical to the build's"

#!/usr/bin/env bash
# convert --cache: the first conversion (a miss: converted and stored) against a second one of the
# same command (a hit), on the built-in scene written as a SIZE² L2 EXR. Prints, best of RUNS, the
# wall seconds and the CPU seconds (user + system, all threads) of each and their ratios;
# docs/asset-cook.md quotes it. On a shared machine the CPU figures are the steadier ones.
# Usage: bench/cache_hit.sh AHDPACK_EXE [SIZE=1024] [PROFILE=pc-bc] [RUNS=3] [extra convert flags…]
set -euo pipefail
cli="$1"; size="${2:-1024}"; profile="${3:-pc-bc}"; runs="${4:-3}"; shift $(( $# < 4 ? $# : 4 ))
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
"$cli" sample --size "$size" -o "$tmp/in.exr" >/dev/null
TIMEFORMAT='%R %U %S'
run() { { time "$cli" convert "$tmp/in.exr" -o "$tmp/o/in.ktx2" --profile "$profile" --cache "$tmp/cache" "$@" > "$tmp/run.log"; } 2> "$tmp/t"; awk '{ print $1, $2 + $3 }' "$tmp/t"; }
min() { awk -v a="$1" -v b="$2" 'BEGIN { print (a < b ? a : b) }'; }
mw=1e9; mc=1e9; hw=1e9; hc=1e9
for r in $(seq "$runs"); do
  rm -rf "$tmp/cache" "$tmp/o"
  read -r w c < <(run "$@"); mw=$(min "$mw" "$w"); mc=$(min "$mc" "$c")
  read -r w c < <(run "$@"); hw=$(min "$hw" "$w"); hc=$(min "$hc" "$c")
  grep -q "cache hit" "$tmp/run.log" || { echo "the second conversion was not a hit"; cat "$tmp/run.log"; exit 1; }
done
{ time "$cli" layouts > /dev/null; } 2> "$tmp/t"
read -r sw su ss < "$tmp/t"
awk -v s="$size" -v p="$profile" -v r="$runs" -v mw="$mw" -v mc="$mc" -v hw="$hw" -v hc="$hc" -v sw="$sw" -v sc="$(awk -v u="$su" -v s="$ss" 'BEGIN{print u+s}')" 'BEGIN {
  printf "%dx%d L2, profile %s, best of %d:\n", s, s, p, r
  printf "  miss (convert + store): %6.2f s wall %6.2f s CPU\n", mw, mc
  printf "  hit:                    %6.2f s wall %6.2f s CPU   (hit/miss: wall %.3f, CPU %.3f)\n", hw, hc, hw / mw, hc / mc
  printf "  (process start alone, ahdpack layouts: %.2f s wall %.2f s CPU)\n", sw, sc }'

#!/usr/bin/env bash
# A generated level of N lightmaps (default 50) of mixed sizes 256²–1024², converted as one batch
# (`ahdpack convert A B C … -o DIR/`) and timed against the sum of OpenImageIO's reads of the same
# files (docs/performance-real.md "Small maps at read speed"). Kinds cycle plain, L1, L2: the plain
# maps are the real Godot plain bake (tests/data/bakes/godot-ragdoll-plain) resized by oiiotool, the
# L1 and L2 maps `ahdpack sample` (seed = index). Sizes cycle 256, 512, 768, 1024, 384.
# Usage: bash scripts/bench-batch.sh [BUILD_DIR] [N] [WORK_DIR]
#   BUILD_DIR  default build/ (its ahdpack);  WORK_DIR  default a fresh folder under /tmp, kept.
# Prints: the batch's user+sys CPU and wall seconds (/usr/bin/time), the summed CPU and wall of one
# OpenImageIO read per file (each in its own process, OpenImageIO loaded before the clock starts:
# `ahdpack bench convert --child read`, with glibc's allocator as an application has it:
# AHD_MALLOC_DEFAULTS=1), and the ratios. ENV: AHD_BATCH_THREADS (default 0 = all),
# AHD_BATCH_EXTRA (more `convert` options, e.g. "--measure off").
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
n=${2:-50}
work=${3:-$(mktemp -d /tmp/ahd-bench-batch.XXXXXX)}
ahdpack=$build/ahdpack
plain_src=tests/data/bakes/godot-ragdoll-plain/ragdoll_physics.exr
command -v oiiotool >/dev/null || { echo "bench-batch: oiiotool (OpenImageIO's tools) is needed for the plain maps" >&2; exit 1; }
[ -x "$ahdpack" ] || { echo "bench-batch: no $ahdpack (build it first)" >&2; exit 1; }
mkdir -p "$work/in"
sizes=(256 512 768 1024 384)
kinds=(plain l1 l2)
files=()
for ((i = 0; i < n; ++i)); do
  s=${sizes[$((i % ${#sizes[@]}))]}
  k=${kinds[$((i % ${#kinds[@]}))]}
  f=$(printf '%s/in/m%02d_%s_%d.exr' "$work" "$i" "$k" "$s")
  if [ ! -f "$f" ]; then
    case $k in
      plain) oiiotool "$plain_src" --resize "${s}x${s}" -d half --compression piz -o "$f" ;;
      l1) "$ahdpack" sample -o "$f" --size "$s" --order 1 --seed "$i" >/dev/null ;;
      l2) "$ahdpack" sample -o "$f" --size "$s" --order 2 --seed "$i" >/dev/null ;;
    esac
  fi
  files+=("$f")
done
echo "bench-batch: $n maps in $work/in ($(du -sh "$work/in" | cut -f1)), load: $(cut -d' ' -f1-3 /proc/loadavg)"

# The sum of the reads: one process per file, the in-process CPU and wall of OpenImageIO's read.
read_cpu=0
read_wall=0
for f in "${files[@]}"; do
  out=$(AHD_MALLOC_DEFAULTS=1 "$ahdpack" bench convert --child read --child-file "$f")
  c=$(sed -n 's/^cpu=//p' <<<"$out")
  w=$(sed -n 's/^seconds=//p' <<<"$out")
  [ -n "$c" ] || { echo "bench-batch: read of $f failed: $out" >&2; exit 1; }
  read_cpu=$(python3 -c "print($read_cpu + $c)")
  read_wall=$(python3 -c "print($read_wall + $w)")
done

rm -rf "$work/out"
# shellcheck disable=SC2086
/usr/bin/time -f "%U %S %e %M" -o "$work/time.txt" "$ahdpack" convert "${files[@]}" -o "$work/out/" -q \
  --threads "${AHD_BATCH_THREADS:-0}" ${AHD_BATCH_EXTRA:-}
read -r u s e m <"$work/time.txt"
python3 - "$u" "$s" "$e" "$m" "$read_cpu" "$read_wall" <<'EOF'
import sys
u, s, e, m, rc, rw = map(float, sys.argv[1:])
print(f"batch convert: cpu {u + s:.2f} s (user {u:.2f}, sys {s:.2f}), wall {e:.2f} s, peak {m / 1024:.0f} MB")
print(f"summed reads:  cpu {rc:.2f} s, wall {rw:.2f} s")
print(f"ratio: cpu {(u + s) / rc:.2f}x, wall {e / rw:.2f}x")
EOF

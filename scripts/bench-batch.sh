#!/usr/bin/env bash
# A generated level of N lightmaps (default 50) of mixed sizes 256²–1024², converted as one batch
# (`ahdpack convert A B C … -o DIR/`) and timed against the sum of OpenImageIO's reads of the same
# files (docs/performance-real.md "Small maps at read speed"). Kinds cycle plain, L1, L2: the plain
# maps are the real Godot plain bake (tests/data/bakes/godot-ragdoll-plain) resized by oiiotool, the
# L1 and L2 maps `ahdpack sample` (seed = index). Sizes cycle 256, 512, 768, 1024, 384.
# Usage: bash scripts/bench-batch.sh [BUILD_DIR] [N] [WORK_DIR] [RUNS]
#   BUILD_DIR  default build/ (its ahdpack);  WORK_DIR  default a fresh folder under /tmp, kept;
#   RUNS  default 3: rounds, each one OpenImageIO read of every file then one batch conversion
#   (interleaved, so a machine that drifts slows both sides alike).
# Prints: the batch's user+sys CPU and wall seconds (/usr/bin/time), the summed CPU and wall of the
# OpenImageIO reads (each in its own process, OpenImageIO loaded before the clock starts:
# `ahdpack bench convert --child read`, with glibc's allocator as an application has it:
# AHD_MALLOC_DEFAULTS=1), and the ratios: the medians over the rounds (the batch's median; each
# file's median read, summed), then each round's own ratio (the spread: single runs of one binary
# gave 1.31x and 1.48x on this VM). ENV: AHD_BATCH_THREADS (default 0 = all), AHD_BATCH_EXTRA
# (more `convert` options, e.g. "--measure off").
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
n=${2:-50}
work=${3:-$(mktemp -d /tmp/ahd-bench-batch.XXXXXX)}
runs=${4:-3}
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

# Each round: one read of every file (its own process: the in-process CPU and wall of OpenImageIO's
# read, one "round file cpu wall" line each), then the batch (one "round u s e m" line).
: >"$work/reads.txt"
: >"$work/batch.txt"
for ((r = 0; r < runs; ++r)); do
  for f in "${files[@]}"; do
    out=$(AHD_MALLOC_DEFAULTS=1 "$ahdpack" bench convert --child read --child-file "$f")
    c=$(sed -n 's/^cpu=//p' <<<"$out")
    w=$(sed -n 's/^seconds=//p' <<<"$out")
    [ -n "$c" ] || { echo "bench-batch: read of $f failed: $out" >&2; exit 1; }
    echo "$r $f $c $w" >>"$work/reads.txt"
  done
  rm -rf "$work/out"
  # shellcheck disable=SC2086
  /usr/bin/time -f "%U %S %e %M" -o "$work/time.txt" "$ahdpack" convert "${files[@]}" -o "$work/out/" -q \
    --threads "${AHD_BATCH_THREADS:-0}" ${AHD_BATCH_EXTRA:-}
  echo "$r $(cat "$work/time.txt")" >>"$work/batch.txt"
done
python3 - "$work/reads.txt" "$work/batch.txt" <<'EOF'
import statistics, sys
from collections import defaultdict
reads, rounds = defaultdict(list), defaultdict(lambda: [0.0, 0.0])
for line in open(sys.argv[1]):
    r, f, c, w = line.split()
    reads[f].append((float(c), float(w)))
    rounds[r][0] += float(c)
    rounds[r][1] += float(w)
batch = {}
for line in open(sys.argv[2]):
    r, u, s, e, m = line.split()
    batch[r] = (float(u), float(s), float(e), float(m))
med = statistics.median
rc = sum(med(c for c, _ in v) for v in reads.values())
rw = sum(med(w for _, w in v) for v in reads.values())
u, s, e, m = (med(b[k] for b in batch.values()) for k in range(4))
cpu = med(b[0] + b[1] for b in batch.values())
print(f"batch convert (median of {len(batch)}): cpu {cpu:.2f} s (user {u:.2f}, sys {s:.2f}), wall {e:.2f} s, peak {m / 1024:.0f} MB")
print(f"summed reads (each file's median): cpu {rc:.2f} s, wall {rw:.2f} s")
print(f"ratio: cpu {cpu / rc:.2f}x, wall {e / rw:.2f}x")
print("each round, cpu / wall ratio: " + ", ".join(
    f"{(b[0] + b[1]) / rounds[r][0]:.2f}x / {b[2] / rounds[r][1]:.2f}x" for r, b in sorted(batch.items())))
EOF

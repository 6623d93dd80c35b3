#!/usr/bin/env bash
# Bounded fuzz run of every libFuzzer target in build-asan/ (built by scripts/sanitize.sh):
# a fixed number of runs per target (RUNS below; FUZZ_RUNS overrides) with a fixed seed, capped at
# FUZZ_SECONDS (default 60) each, seeded from the golden files and presets.
# A crash, sanitizer report, leak, timeout or out-of-memory fails the run; the reproducer is left
# in build-asan/fuzz-artifacts/. Usage: bash scripts/fuzz.sh [target ...]
set -euo pipefail
cd "$(dirname "$0")/.."
B=build-asan
T="${FUZZ_SECONDS:-60}"
[ -x "$B/fuzz/fuzz_ktx2" ] || bash scripts/sanitize.sh --build-only
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
corpus="$B/fuzz-corpus"
rm -rf "$corpus"
mkdir -p "$B/fuzz-artifacts"
seed() {  # seed TARGET FILES...
  local t=$1; shift
  mkdir -p "$corpus/$t"
  for f in "$@"; do [ -f "$f" ] && cp "$f" "$corpus/$t/"; done
  return 0
}
seed ktx2 golden/expected/*.ktx2
seed dds golden/expected/*.dds
seed manifest $(ls golden/expected/*.json | grep -v report)
seed layout formats/bakers/*.json
seed blocks golden/expected/*.iz.*
seed report golden/expected/*.report.json
# The intermediate EXR of a golden input; small meshes (byte 0 picks .obj / .gltf / .glb).
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
A="$B/ahdpack"; [ -x "$A" ] || A=build/ahdpack
ASAN_OPTIONS=detect_leaks=0 "$A" convert golden/inputs/scene13_l1_seed3.exr -o "$tmp/x.ktx2" --keep-intermediate -q
seed intermediate "$tmp/x.ahd.exr"
mkdir -p "$corpus/mesh"
printf '\000v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 2/2/1 4/4/1 3/3/1\n' >"$corpus/mesh/quad.obj"
printf '\000o a\nv 0 0 0\nv 2 0 0\nv 0 2 1\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\nf 1/1 2/2 3/3\ng b\nf 1/4 2/2 3/1\n' >"$corpus/mesh/two.obj"
failed=0
# A fixed number of runs per target with a fixed seed: the same inputs are tried on every machine,
# so a run that passed here passes in CI (FUZZ_SECONDS only caps the time on a slow machine, which
# then tries a prefix of the same sequence). About 30 s each on this 2-core machine.
declare -A RUNS=([ktx2]=600000 [dds]=1000000 [manifest]=100000 [layout]=60000 [intermediate]=500 [blocks]=60000 [mesh]=300 [report]=50000)
for t in ${@:-ktx2 dds manifest layout intermediate blocks mesh report}; do
  extra=(-runs="${FUZZ_RUNS:-${RUNS[$t]}}")
  # OpenEXR and Assimp are not instrumented and keep caches of their own: leaks are only ours to find elsewhere.
  case $t in intermediate|mesh) extra+=(-detect_leaks=0) ;; esac
  if ! "$B/fuzz/fuzz_$t" "$corpus/$t" -max_total_time="$T" -seed=1 -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=1024 -artifact_prefix="$B/fuzz-artifacts/$t-" -print_final_stats=1 "${extra[@]}" \
      >"$B/fuzz-artifacts/$t.log" 2>&1; then
    echo "fuzz: $t FAILED (see $B/fuzz-artifacts/$t.log)"; tail -30 "$B/fuzz-artifacts/$t.log"; failed=1
  else
    echo "fuzz: $t ok ($(grep -o 'stat::number_of_executed_units: *[0-9]*' "$B/fuzz-artifacts/$t.log" | grep -o '[0-9]*$') runs)"
  fi
done
exit $failed

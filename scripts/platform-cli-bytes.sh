#!/usr/bin/env bash
# The CLI's conversions for the cross-platform comparison (docs/platforms.md), the file edge
# included: the built-in sample, the vermilion Godot project and a real plain map, each with
# --profile pc-bc and --profile uncompressed (six conversions, CASES below).
#   bash scripts/platform-cli-bytes.sh run OUTDIR [--] [RUNNER...] AHDPACK
#       runs the conversions with `RUNNER... AHDPACK convert ...` (RUNNER empty when native,
#       `qemu-aarch64 -L /` for Arm64, `wine` for Windows), each into OUTDIR/<case>/, and keeps the
#       planes and manifests (the reports are deleted: they hold seconds)
#   bash scripts/platform-cli-bytes.sh reference OUTDIR AHDPACK
#       the x86-64 reference: `run` once per SIMD path (AHD_CPU_DISABLE, src/cli/environment.h: all,
#       AVX2 at most, SSE2 loops only, plain scalar) into OUTDIR/x86-64-<path>/, and checks the four
#       give the same bytes
#   bash scripts/platform-cli-bytes.sh compare REF_DIR OTHER_DIR
#       every file of either folder byte-identical in the other (scripts/compare-platform-bytes.sh)
# Run from anywhere; the script works from the repository root, and the paths it passes to the CLI
# (inputs under tests/data, OUTDIR) are relative to it when OUTDIR is (as a Wine run needs): give
# OUTDIR and AHDPACK relative to the repository root, or absolute for native and qemu runs.
# Exit 0 only when every conversion succeeds (and, for reference and compare, the bytes agree).
set -euo pipefail
cd "$(dirname "$0")/.."

# case name, input (empty: the built-in sample), output file name, options
CASES=(
  "sample-pc-bc||sample.ktx2|--profile pc-bc"
  "sample-uncompressed||sample.ktx2|--profile uncompressed"
  "vermilion-pc-bc|tests/data/bakes/godot42-vermilion/project/scenes/world.exr|world.ktx2|--profile pc-bc"
  "vermilion-uncompressed|tests/data/bakes/godot42-vermilion/project/scenes/world.exr|world.ktx2|--profile uncompressed"
  "plain-pc-bc|tests/data/bakes/godot-ragdoll-plain/ragdoll_physics.exr|ragdoll_physics.ktx2|--profile pc-bc"
  "plain-uncompressed|tests/data/bakes/godot-ragdoll-plain/ragdoll_physics.exr|ragdoll_physics.ktx2|--profile uncompressed"
)

usage() { sed -n '2,18p' "$0" >&2; exit 2; }

run() {  # OUTDIR RUNNER... AHDPACK
  local out=$1; shift
  [ "${1:-}" = -- ] && shift
  [ $# -ge 1 ] || usage
  local cmd=("$@") log c name input file opts start
  log=$(mktemp)
  rm -rf "$out"
  for c in "${CASES[@]}"; do
    IFS='|' read -r name input file opts <<<"$c"
    mkdir -p "$out/$name"
    start=$(date +%s)
    # shellcheck disable=SC2086  # opts: several words
    local rc=0
    "${cmd[@]}" convert $input -o "$out/$name/$file" $opts >"$log" 2>&1 || rc=$?
    # A run that failed without a word (no report, no error line: Wine's process start failed
    # once in a CI check on 2026-12-05, and the same command then passed three times) is run
    # again once, saying so; a conversion's own failure always prints its error line.
    if [ $rc != 0 ] && [ ! -s "$log" ]; then
      echo "platform-cli-bytes: $name exited $rc without output: running it again" >&2
      rm -rf "${out:?}/$name" && mkdir -p "$out/$name"
      # shellcheck disable=SC2086
      rc=0 && "${cmd[@]}" convert $input -o "$out/$name/$file" $opts >"$log" 2>&1 || rc=$?
    fi
    if [ $rc != 0 ]; then
      echo "platform-cli-bytes: $name failed (exit $rc): ${cmd[*]} convert $input -o $out/$name/$file $opts" >&2
      cat "$log" >&2; rm -f "$log"; return 1
    fi
    rm -f "$out/$name"/*.report.json
    echo "$name: $(( $(date +%s) - start )) s, $(find "$out/$name" -type f | wc -l) files"
  done
  rm -f "$log"
}

case ${1:-} in
  run)
    [ $# -ge 3 ] || usage
    shift; run "$@"
    ;;
  reference)
    [ $# = 3 ] || usage
    out=$2 exe=$3
    # Masks of ahd::cpu::disable_for_tests (src/core/cpu.h): 0 all, 8 no AVX-512, 30 SSE2 only, 31 none.
    for p in all:0 avx2:8 sse2:30 scalar:31; do
      echo "x86-64-${p%%:*}:"
      (export AHD_CPU_DISABLE=${p#*:}; run "$out/x86-64-${p%%:*}" "$exe")
    done
    for p in avx2 sse2 scalar; do bash scripts/compare-platform-bytes.sh compare "$out/x86-64-all" "$out/x86-64-$p"; done
    ;;
  compare)
    [ $# = 3 ] || usage
    bash scripts/compare-platform-bytes.sh compare "$2" "$3"
    ;;
  *) usage ;;
esac

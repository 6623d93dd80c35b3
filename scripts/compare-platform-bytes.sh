#!/usr/bin/env bash
# The x86-64 reference for the cross-platform comparison, and the comparison itself.
#   bash scripts/compare-platform-bytes.sh reference [BUILD_DIR]
#       builds the library-only x86-64 build (BUILD_DIR, default build-x86), runs
#       ahd_platform_bytes once per SIMD path (all, AVX2 at most, SSE2 loops only, plain scalar) into
#       BUILD_DIR/platform-bytes/x86-64-<path>/, and checks the four give the same bytes
#   bash scripts/compare-platform-bytes.sh compare REF_DIR OTHER_DIR
#       every file of either folder byte-identical in the other (exit 1 and the differing files if not)
# docs/platforms.md "What was run where".
set -euo pipefail
cd "$(dirname "$0")/.."

compare() {
  local a=$1 b=$2 bad=0 n=0
  [ -d "$a" ] && [ -d "$b" ] || { echo "compare-platform-bytes: $a or $b: no such folder" >&2; return 1; }
  while IFS= read -r f; do
    n=$((n + 1))
    if [ ! -f "$b/$f" ]; then echo "only in $a: $f"; bad=1
    elif ! cmp -s "$a/$f" "$b/$f"; then echo "differs: $f"; bad=1; fi
  done < <(cd "$a" && find . -type f | sort)
  while IFS= read -r f; do
    [ -f "$a/$f" ] || { echo "only in $b: $f"; bad=1; }
  done < <(cd "$b" && find . -type f | sort)
  if [ $bad = 0 ]; then echo "same bytes: $n files ($a = $b)"; fi
  return $bad
}

case ${1:-} in
  reference)
    build=${2:-build-x86}
    export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD/..} CCACHE_DIR=${CCACHE_DIR:-$PWD/../.ccache}
    launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_UNITY_BUILD=OFF -DAHD_LIBRARY_ONLY=ON \
      "${launcher[@]}" >/dev/null
    nice -n 19 cmake --build "$build" -j2 --target ahd_platform_bytes
    out=$build/platform-bytes
    rm -rf "$out"
    # Masks of ahd::cpu::disable_for_tests (src/core/cpu.h): 0 all, 8 no AVX-512, 30 SSE2 only, 31 none.
    for p in all:0 avx2:8 sse2:30 scalar:31; do
      "$build/tests/platforms/ahd_platform_bytes" "$out/x86-64-${p%%:*}" --disable "${p#*:}" >/dev/null
    done
    for p in avx2 sse2 scalar; do compare "$out/x86-64-all" "$out/x86-64-$p"; done
    ;;
  compare)
    compare "$2" "$3"
    ;;
  *)
    sed -n '2,9p' "$0" >&2
    exit 2
    ;;
esac

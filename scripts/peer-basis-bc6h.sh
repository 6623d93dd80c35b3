#!/usr/bin/env bash
# Side-by-side BC6H speed and error of Basis Universal's real-time encoder (HQ defaults and its
# 9-mode/32-pattern setting) and ahdpack (`fast` and `default`; QUALITIES overrides) on this
# machine, on tests/data/bc6h and the real-lightmap corpus bench/data/real, each pinned to the
# same CPU (bench/peers/basis_bc6h.cpp says why).
# Usage: bash scripts/peer-basis-bc6h.sh BASIS_UNIVERSAL_CHECKOUT [CPU ...]   (default CPUs: all)
#        QUALITIES="fast default max" bash scripts/peer-basis-bc6h.sh ...
#        EXTRA_DIR=DIR bash scripts/peer-basis-bc6h.sh ...   (also every EXR of DIR, e.g. the truth bakes' I_z)
# Needs a built ./build (README command 1 or 2). Builds into build/peers/; nothing of the checkout
# is copied into the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
basis="$(cd "${1:?usage: peer-basis-bc6h.sh BASIS_UNIVERSAL_CHECKOUT [CPU ...]}" && pwd)"
shift
cpus=("$@")
[ ${#cpus[@]} -gt 0 ] || mapfile -t cpus < <(seq 0 $(($(nproc) - 1)))
images=(tests/data/bc6h/lightmap_smooth.exr tests/data/bc6h/hdr_hard.exr tests/data/bc6h/lightmap_noisy.exr
        bench/data/real/*.exr)
extra=()
if [ -n "${EXTRA_DIR:-}" ]; then
  images+=("$EXTRA_DIR"/*.exr)
  extra=("$EXTRA_DIR")
fi
read -r -a qualities <<< "${QUALITIES:-fast default}"
mkdir -p build/peers
if [ ! -x build/peers/basis_bc6h ] || [ bench/peers/basis_bc6h.cpp -nt build/peers/basis_bc6h ]; then
  [ -f build/peers/basisu_transcoder.o ] ||
    g++ -std=c++17 -O2 -march=native -I "$basis" -c "$basis/transcoder/basisu_transcoder.cpp" -o build/peers/basisu_transcoder.o
  g++ -std=c++20 -O2 -march=native -I "$basis" -I src -I include bench/peers/basis_bc6h.cpp build/peers/basisu_transcoder.o \
    build/libahd_io.a build/libahd_sample.a build/libahd.a -lOpenImageIO -lOpenImageIO_Util $(pkg-config --libs OpenEXR OpenColorIO) \
    -lImath -lzstd -lassimp -ldl -lpthread -o build/peers/basis_bc6h
fi
for cpu in "${cpus[@]}"; do
  echo "== CPU $cpu (load $(cut -d' ' -f1-3 /proc/loadavg))"
  taskset -c "$cpu" build/peers/basis_bc6h "${images[@]}"
  taskset -c "$cpu" build/ahdpack bench bc6h ${extra[@]:+tests/data/bc6h bench/data/real "${extra[@]}"} \
    --qualities "${qualities[@]}" --codecs bc6h | tail -n +3
done

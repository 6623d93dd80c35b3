#!/usr/bin/env bash
# Arm64: cross-build the library with Debian's g++-aarch64-linux-gnu, run its unit tests and the
# byte comparison under qemu-aarch64 (docs/platforms.md "Arm64").
#   bash scripts/cross-arm64.sh [--no-install] [--bytes-only|--tests-only]
# Installs (as root, unless --no-install) the cross compiler, qemu-user and the arm64 -dev packages
# through multiarch; builds build-arm64/ (AHD_LIBRARY_ONLY, cmake/toolchains/aarch64-linux-gnu.cmake)
# and the x86-64 reference build-x86/; runs ahd_platform_tests under qemu, then ahd_platform_bytes,
# whose planes and manifests must equal the x86-64 ones byte for byte. Exit 0 only when all pass.
set -euo pipefail
cd "$(dirname "$0")/.."
install=1 tests=1 bytes=1
for a in "$@"; do
  case $a in
    --no-install) install=0 ;;
    --bytes-only) tests=0 ;;
    --tests-only) bytes=0 ;;
    *) sed -n '2,8p' "$0" >&2; exit 2 ;;
  esac
done

if [ $install = 1 ] && ! { command -v aarch64-linux-gnu-g++ && command -v qemu-aarch64 &&
    [ -f /usr/lib/aarch64-linux-gnu/libzstd.a ] && [ -d /usr/lib/aarch64-linux-gnu/cmake/Imath ] &&
    [ -d /usr/src/googletest ]; } >/dev/null; then
  dpkg --add-architecture arm64
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends g++-aarch64-linux-gnu qemu-user \
    libzstd-dev:arm64 libimath-dev:arm64 nlohmann-json3-dev googletest ninja-build cmake pkg-config
fi

export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD/..} CCACHE_DIR=${CCACHE_DIR:-$PWD/../.ccache}
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
build=build-arm64
cmake -S . -B $build -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_UNITY_BUILD=OFF -DAHD_LIBRARY_ONLY=ON \
  -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/toolchains/aarch64-linux-gnu.cmake" "${launcher[@]}" >/dev/null
nice -n 19 cmake --build $build -j2 --target ahd_platform_tests ahd_platform_bytes

# -L /: the loader and libc of libc6:arm64 (see the toolchain file).
run=(nice -n 19 qemu-aarch64 -L /)
if [ $tests = 1 ]; then
  start=$(date +%s)
  "${run[@]}" $build/tests/platforms/ahd_platform_tests --gtest_brief=1
  echo "arm64 unit tests under qemu: $(( $(date +%s) - start )) s"
fi
if [ $bytes = 1 ]; then
  bash scripts/compare-platform-bytes.sh reference build-x86
  rm -rf $build/platform-bytes
  start=$(date +%s)
  "${run[@]}" $build/tests/platforms/ahd_platform_bytes $build/platform-bytes/arm64 >/dev/null
  echo "arm64 conversions under qemu: $(( $(date +%s) - start )) s"
  bash scripts/compare-platform-bytes.sh compare build-x86/platform-bytes/x86-64-all $build/platform-bytes/arm64
fi

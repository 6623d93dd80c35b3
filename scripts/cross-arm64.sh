#!/usr/bin/env bash
# Arm64: cross-build the library, the file edge and the CLI with Debian's g++-aarch64-linux-gnu,
# run the library's unit tests and both byte comparisons under qemu-aarch64 (docs/platforms.md "Arm64").
#   bash scripts/cross-arm64.sh [--no-install] [--bytes-only|--tests-only]
# Installs (as root, unless --no-install) the cross compiler, qemu-user and the arm64 packages
# through multiarch; unpacks the two arm64 -dev packages multiarch cannot install beside the host's
# (libopenexr-dev, libopencolorio-dev) into BUILD/sysroot; builds BUILD (default build-arm64, or
# $AHD_ARM64_BUILD_DIR; cmake/toolchains/aarch64-linux-gnu.cmake, no OpenImageIO module), the
# library-only x86-64 reference build-x86/ and the x86-64 ahdpack in build/; runs under qemu
# ahd_platform_tests, ahd_platform_bytes (library conversions) and ahdpack's conversions
# (scripts/platform-cli-bytes.sh), whose planes and manifests must equal the x86-64 ones byte for
# byte (the x86-64 references: every SIMD path, identical). AHD_WERROR=ON: warnings are errors.
# Exit 0 only when all pass.
set -euo pipefail
cd "$(dirname "$0")/.."
install=1 tests=1 bytes=1
for a in "$@"; do
  case $a in
    --no-install) install=0 ;;
    --bytes-only) tests=0 ;;
    --tests-only) bytes=0 ;;
    *) sed -n '2,13p' "$0" >&2; exit 2 ;;
  esac
done
build=${AHD_ARM64_BUILD_DIR:-build-arm64}
arch=/usr/lib/aarch64-linux-gnu

# Runtime libraries and -dev packages that multiarch installs beside the host's amd64 ones
# (checked with apt-get install -s: nothing is removed). libopenexr-dev:arm64 and
# libopencolorio-dev:arm64 are not among them (files shared with the amd64 -dev packages differ):
# their runtimes are, and the -dev packages are unpacked below. OpenImageIO is not needed
# (AHD_OIIO_MODULE=OFF: EXR inputs read through OpenEXR). Assimp stays a module (AHD_ASSIMP_MODULE
# ON, as on x86-64): the CLI's conversions under qemu open build-arm64/libahd_assimp.so.
arm64_pkgs=(libzstd-dev:arm64 libimath-dev:arm64 zlib1g-dev:arm64 libassimp-dev:arm64
  libopenexr-3-1-30:arm64 libopencolorio2.1:arm64)
if [ $install = 1 ] && ! { command -v aarch64-linux-gnu-g++ && command -v qemu-aarch64 &&
    [ -f $arch/libzstd.a ] && [ -d $arch/cmake/Imath ] && [ -f $arch/libz.so ] && [ -f $arch/libassimp.so ] &&
    [ -f $arch/libOpenEXR-3_1.so.30 ] && [ -f $arch/libOpenColorIO.so.2.1 ] &&
    [ -d /usr/src/googletest ] && [ -f /usr/include/CLI/CLI.hpp ]; } >/dev/null; then
  dpkg --add-architecture arm64
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends g++-aarch64-linux-gnu qemu-user \
    "${arm64_pkgs[@]}" nlohmann-json3-dev libcli11-dev googletest ninja-build cmake pkg-config
fi

# BUILD/sysroot: libopenexr-dev, its runtime (its CMake files name the library files beside them)
# and libopencolorio-dev, unpacked; the .pc file's prefix and the symbolic links into the runtime
# packages point into the sysroot or at the installed libraries.
case $build in /*) sysroot=$build/sysroot ;; *) sysroot=$PWD/$build/sysroot ;; esac
if [ ! -f "$sysroot/.done" ]; then
  rm -rf "$sysroot" "$build/debs"; mkdir -p "$sysroot" "$build/debs"
  (cd "$build/debs" && apt-get download libopenexr-dev:arm64 libopenexr-3-1-30:arm64 libopencolorio-dev:arm64)
  for d in "$build"/debs/*.deb; do dpkg -x "$d" "$sysroot"; done
  sed -i "s|^prefix=/usr\$|prefix=$sysroot/usr|" "$sysroot/usr/lib/aarch64-linux-gnu/pkgconfig/"*.pc
  (cd "$sysroot/usr/lib/aarch64-linux-gnu" &&
    find . -maxdepth 1 -xtype l -print0 | while IFS= read -r -d '' l; do ln -sfn "$arch/$(readlink "$l")" "$l"; done)
  touch "$sysroot/.done"
fi

export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD/..} CCACHE_DIR=${CCACHE_DIR:-$PWD/../.ccache}
# CCACHE_DISABLE=1: compiled without ccache (a cold build, as measured in docs/platforms.md).
launcher=(); command -v ccache >/dev/null && [ -z "${CCACHE_DISABLE:-}" ] && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
werror=(-DAHD_WARNINGS_AS_ERRORS="${AHD_WERROR:-OFF}")
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_UNITY_BUILD=OFF -DAHD_LIBRARY_ONLY=OFF \
  -DAHD_OIIO_MODULE=OFF -DAHD_PLATFORM_TESTS_ONLY=ON -DAHD_BUILD_BENCH=OFF -DAHD_ARM64_SYSROOT="$sysroot" \
  -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/toolchains/aarch64-linux-gnu.cmake" "${launcher[@]}" "${werror[@]}" >/dev/null
start=$(date +%s)
nice -n 19 cmake --build "$build" -j2 --target ahdpack ahd_platform_tests ahd_platform_bytes
echo "arm64 build: $(( $(date +%s) - start )) s"

# -L /: the loader and libc of libc6:arm64 (see the toolchain file).
run=(nice -n 19 qemu-aarch64 -L /)
if [ $tests = 1 ]; then
  start=$(date +%s)
  "${run[@]}" "$build"/tests/platforms/ahd_platform_tests --gtest_brief=1
  echo "arm64 unit tests under qemu: $(( $(date +%s) - start )) s"
fi
if [ $bytes = 1 ]; then
  # The library's conversions (ahd_platform_bytes).
  bash scripts/compare-platform-bytes.sh reference build-x86
  rm -rf "$build"/platform-bytes
  start=$(date +%s)
  "${run[@]}" "$build"/tests/platforms/ahd_platform_bytes "$build"/platform-bytes/arm64 >/dev/null
  echo "arm64 conversions under qemu: $(( $(date +%s) - start )) s"
  bash scripts/compare-platform-bytes.sh compare build-x86/platform-bytes/x86-64-all "$build"/platform-bytes/arm64

  # The CLI's conversions: x86-64's ahdpack of build/ (configured as scripts/build.sh does when
  # missing; built or brought up to date here), then Arm64's under qemu.
  [ -f build/CMakeCache.txt ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
    "${werror[@]}" >/dev/null
  nice -n 19 cmake --build build -j2 --target ahdpack
  bash scripts/platform-cli-bytes.sh reference build-x86/cli-bytes build/ahdpack
  start=$(date +%s)
  bash scripts/platform-cli-bytes.sh run "$build"/cli-bytes/arm64 -- "${run[@]}" "$build"/ahdpack
  echo "arm64 CLI conversions under qemu: $(( $(date +%s) - start )) s"
  bash scripts/platform-cli-bytes.sh compare build-x86/cli-bytes/x86-64-all "$build"/cli-bytes/arm64
fi

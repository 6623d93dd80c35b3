#!/usr/bin/env bash
# Windows x86-64: cross-build the library with Debian's MinGW-w64, run its unit tests and the byte
# comparison under Wine (docs/platforms.md "Windows").
#   bash scripts/cross-windows.sh [--no-install] [--bytes-only|--tests-only]
# Installs (as root, unless --no-install) MinGW-w64 (posix threads) and Wine; builds zstd and Imath,
# which Debian does not ship for MinGW, from Debian's source packages (apt-get source; a deb-src
# line for the system's suites is added when none is configured) into build-win/deps/prefix; builds
# build-win/ (AHD_LIBRARY_ONLY, cmake/toolchains/x86_64-w64-mingw32.cmake) and the x86-64 reference
# build-x86/; runs ahd_platform_tests.exe under Wine in a fresh WINEPREFIX, then
# ahd_platform_bytes.exe, whose planes and manifests must equal the x86-64 ones byte for byte.
set -euo pipefail
cd "$(dirname "$0")/.."
install=1 tests=1 bytes=1
for a in "$@"; do
  case $a in
    --no-install) install=0 ;;
    --bytes-only) tests=0 ;;
    --tests-only) bytes=0 ;;
    *) sed -n '2,10p' "$0" >&2; exit 2 ;;
  esac
done
build=build-win
deps=$PWD/$build/deps
prefix=$deps/prefix
toolchain=$PWD/cmake/toolchains/x86_64-w64-mingw32.cmake

if [ $install = 1 ] && ! { command -v x86_64-w64-mingw32-g++-posix && command -v wine && [ -d /usr/src/googletest ]; } >/dev/null; then
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends g++-mingw-w64-x86-64-posix wine wine64 \
    nlohmann-json3-dev googletest dpkg-dev ninja-build cmake pkg-config
fi

# zstd and Imath from Debian's source packages, static, for MinGW.
if [ ! -f "$prefix/lib/libzstd.a" ] || [ ! -f "$prefix/lib/libImath-3_1.a" ]; then
  mkdir -p "$deps"
  if ! grep -rqs '^Types:.*deb-src\|^deb-src' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    [ $install = 1 ] || { echo "cross-windows: no deb-src line in apt's sources (needed for zstd and Imath)" >&2; exit 1; }
    suite=$(. /etc/os-release && echo "$VERSION_CODENAME")
    printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: %s\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
      "$suite" > /etc/apt/sources.list.d/ahdpack-deb-src.sources
    apt-get update -q
  fi
  (cd "$deps" && rm -rf libzstd-* imath-* && apt-get source -q libzstd imath >/dev/null)
  zstd_src=$(find "$deps" -maxdepth 1 -type d -name 'libzstd-*' | head -1)
  imath_src=$(find "$deps" -maxdepth 1 -type d -name 'imath-*' | head -1)
  cmake -S "$zstd_src/build/cmake" -B "$deps/zstd-build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DCMAKE_INSTALL_PREFIX="$prefix" -DZSTD_BUILD_PROGRAMS=OFF \
    -DZSTD_BUILD_SHARED=OFF -DZSTD_BUILD_TESTS=OFF -DZSTD_MULTITHREAD_SUPPORT=OFF >/dev/null
  nice -n 19 cmake --build "$deps/zstd-build" -j2 --target install >/dev/null
  cmake -S "$imath_src" -B "$deps/imath-build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DCMAKE_INSTALL_PREFIX="$prefix" -DBUILD_SHARED_LIBS=OFF \
    -DBUILD_TESTING=OFF -DPYTHON=OFF >/dev/null
  nice -n 19 cmake --build "$deps/imath-build" -j2 --target install >/dev/null
fi

# nlohmann_json is header-only, but its package names /usr/include, whose glibc headers would
# shadow MinGW's: a copy of the headers and CMake files in the prefix points at the prefix instead.
if [ ! -f "$prefix/include/nlohmann/json.hpp" ]; then
  mkdir -p "$prefix/include" "$prefix/share/cmake"
  cp -r /usr/include/nlohmann "$prefix/include/"
  cp -r /usr/share/cmake/nlohmann_json "$prefix/share/cmake/"
fi

export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD/..} CCACHE_DIR=${CCACHE_DIR:-$PWD/../.ccache}
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B $build -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_UNITY_BUILD=OFF -DAHD_LIBRARY_ONLY=ON \
  -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DAHD_WIN_DEPS_PREFIX="$prefix" "${launcher[@]}" >/dev/null
nice -n 19 cmake --build $build -j2 --target ahd_platform_tests ahd_platform_bytes

# A fresh Wine prefix per run: nothing of an earlier run (or of the user's ~/.wine) is reused.
WINEPREFIX=$(mktemp -d "${TMPDIR:-/tmp}/ahd-wine.XXXXXX")
export WINEPREFIX WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
trap 'wineserver -k >/dev/null 2>&1 || true; rm -rf "$WINEPREFIX"' EXIT
run=(nice -n 19 wine)
if [ $tests = 1 ]; then
  start=$(date +%s)
  "${run[@]}" $build/tests/platforms/ahd_platform_tests.exe --gtest_brief=1
  echo "windows unit tests under wine: $(( $(date +%s) - start )) s"
fi
if [ $bytes = 1 ]; then
  bash scripts/compare-platform-bytes.sh reference build-x86
  rm -rf $build/platform-bytes
  start=$(date +%s)
  "${run[@]}" $build/tests/platforms/ahd_platform_bytes.exe $build/platform-bytes/windows >/dev/null
  echo "windows conversions under wine: $(( $(date +%s) - start )) s"
  bash scripts/compare-platform-bytes.sh compare build-x86/platform-bytes/x86-64-all $build/platform-bytes/windows
fi
